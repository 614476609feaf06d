#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ (clang, ASan + UBSan) into build-fuzz/ and runs each
# for FUZZ_SECONDS (default 15). Fails on any crash, leak, timeout or allocation over the
# limits below that its saved input reproduces; the input is kept in build-fuzz/findings/.
# A finding whose input does not reproduce it (a loaded machine's timeout, a sanitizer's own
# fatal error) is reported as unconfirmed and does not fail the run. Every finding is
# summarised in build-fuzz/findings/summary.txt, confirmed inputs base64-encoded, because CI
# shows only the end of its output.
# Usage: scripts/fuzz.sh [target...]   (default: every target)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$here/build-fuzz"
seconds="${FUZZ_SECONDS:-15}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_COMPILER=clang++ \
  -DISOCORR_FUZZ=ON -DISOCORR_SANITIZE=address,undefined -DISOCORR_BUILD_TESTS=OFF -DISOCORR_BUILD_SERVICE=OFF -DISOCORR_ARCH=auto \
  "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$(nproc)"

# Seed corpus: generated valid inputs plus the hand-written malformed ones of fuzz/seeds/.
"$build/fuzz/isocorr-fuzz-seeds" "$build/seeds"
declare -A seed_dirs=(
  [fuzz_mesh_off]="mesh_off" [fuzz_mesh_obj]="mesh_obj" [fuzz_mesh_ply]="mesh_ply"
  [fuzz_mesh_upload]="mesh_off mesh_obj mesh_ply" [fuzz_map_file]="map_file"
  [fuzz_settings_json]="settings_json" [fuzz_job_record]="job_record")
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_mesh_off fuzz_mesh_obj fuzz_mesh_ply fuzz_mesh_upload fuzz_map_file
                                      fuzz_settings_json fuzz_job_record)

# One input may take 10 s and 512 MB in one allocation, 2 GB in all; more is a finding.
limits=(-timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=512 -detect_leaks=1)
findings="$build/findings"
summary="$findings/summary.txt"
mkdir -p "$findings"
rm -f "$summary"

# The first lines that say what went wrong, from a libFuzzer or sanitizer log.
error_lines() {
  grep -m 4 -E 'ERROR|SUMMARY|contract broken|ALARM|Timeout|timeout|out-of-memory|malloc\(|deadly signal|fatal error' "$1" || true
}

# Runs each input the failed run saved (those newer than its start marker) once more.
# Succeeds if one fails again, and records every input in the summary.
reproduce() {
  local target="$1" reproduced=1 artifact
  for artifact in "$findings/$target"-*; do
    case "$artifact" in *.log) continue ;; esac
    [ -f "$artifact" ] && [ "$artifact" -nt "$findings/.start-$target" ] || continue
    if "$build/fuzz/$target" "${limits[@]}" "$artifact" >"$artifact-replay.log" 2>&1; then
      echo "  $(basename "$artifact"): passes when run again" >>"$summary"
    else
      reproduced=0
      echo "  $(basename "$artifact"): fails again; $(stat -c %s "$artifact") bytes, base64:" >>"$summary"
      head -c 4096 "$artifact" | base64 -w 100 | sed 's/^/    /' >>"$summary"
      error_lines "$artifact-replay.log" | sed 's/^/    /' >>"$summary"
    fi
  done
  return $reproduced
}

failed=()
for target in "${targets[@]}"; do
  [ -n "${seed_dirs[$target]:-}" ] || { echo "fuzz: unknown target $target" >&2; exit 2; }
  corpus="$build/corpus/$target"  # grows across local runs; CI starts from the seeds
  mkdir -p "$corpus"
  inputs=("$corpus")
  for d in ${seed_dirs[$target]}; do inputs+=("$build/seeds/$d" "$here/fuzz/seeds/$d"); done
  touch "$findings/.start-$target"
  echo "fuzz: $target for ${seconds}s"
  if ! "$build/fuzz/$target" -max_total_time="$seconds" "${limits[@]}" -print_final_stats=1 \
        -artifact_prefix="$findings/$target-" "${inputs[@]}" >"$findings/$target.log" 2>&1; then
    tail -n 60 "$findings/$target.log"
    {
      echo "$target:"
      error_lines "$findings/$target.log" | sed 's/^/  /'
    } >>"$summary"
    if reproduce "$target"; then
      failed+=("$target")
    else
      echo "  unconfirmed: no saved input fails again" >>"$summary"
    fi
  fi
  # A run that stopped on a finding prints no statistics.
  { grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb)' "$findings/$target.log" || true; } | tr '\n' ' '
  echo
done
[ -f "$summary" ] && { echo "fuzz: findings"; cat "$summary"; }
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs in $findings/)" >&2
  exit 1
fi
if [ -f "$summary" ]; then
  echo "fuzz: all ${#targets[@]} targets clean: no finding reproduced from its saved input"
else
  echo "fuzz: all ${#targets[@]} targets clean"
fi
