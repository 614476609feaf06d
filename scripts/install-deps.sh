#!/usr/bin/env bash
# Installs the Debian packages that this machine lacks: those of deploy/packages-engine.txt
# and deploy/packages.txt, or with --engine-only those of the engine alone.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
lists=("$here/deploy/packages-engine.txt")
[ "${1:-}" = "--engine-only" ] || lists+=("$here/deploy/packages.txt")
mapfile -t wanted < <(cat "${lists[@]}" | grep -v '^\s*#' | grep -v '^\s*$')
missing=()
for pkg in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'install ok installed' || missing+=("$pkg")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#wanted[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=""
[ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
$sudo_cmd apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
