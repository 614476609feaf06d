#!/usr/bin/env bash
# The hardening phases of CI, after scripts/test.sh: every fuzz target for a bounded time,
# the suite under ASan + UBSan, then under TSan. Runs every phase, reports each one's time,
# and fails if any failed.
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
failed=()
timings=()
phase() {
  local name="$1"
  shift
  echo "=== hardening: $name"
  local start=$SECONDS
  "$@" || failed+=("$name")
  timings+=("$(printf '%-6s %4d s' "$name" $((SECONDS - start)))")
}
phase fuzz "$here/scripts/fuzz.sh"
phase asan "$here/scripts/sanitize.sh" asan
phase tsan "$here/scripts/sanitize.sh" tsan
printf '=== hardening times\n'
printf '  %s\n' "${timings[@]}"
# Repeated here because CI shows only the end of its output.
fuzz_summary="$here/build-fuzz/findings/summary.txt"
[ -f "$fuzz_summary" ] && { echo "=== fuzz findings"; cat "$fuzz_summary"; }
if [ ${#failed[@]} -ne 0 ]; then
  echo "hardening: FAILED: ${failed[*]}" >&2
  exit 1
fi
echo "hardening: all phases clean"
