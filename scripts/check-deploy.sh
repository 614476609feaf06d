#!/usr/bin/env bash
# Checks deploy/ (Kubernetes manifests, compose, the Envoy config) and the Dockerfile by
# parsing them, against the flags the built isocorr-server takes: no cluster runs in CI.
# First proves on broken copies that the checks catch what they claim to.
# usage: scripts/check-deploy.sh [PATH/TO/isocorr-server]   (default build/server/isocorr-server)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
server="${1:-$here/build/server/isocorr-server}"
help="$(mktemp)"
trap 'rm -f "$help"' EXIT
"$server" --help > "$help"
python3 "$here/scripts/check_deploy.py" --self-test "$here" "$help"
python3 "$here/scripts/check_deploy.py" "$here" "$help"
echo "check-deploy: deploy/ and the Dockerfile agree with isocorr-server --help"
