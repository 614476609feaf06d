#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ (clang, ASan + UBSan) into build-fuzz/ and runs each
# for FUZZ_SECONDS (default 15). Fails on any crash, leak, timeout or allocation over the
# limits below; the offending input is kept in build-fuzz/findings/.
# Usage: scripts/fuzz.sh [target...]   (default: every target)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$here/build-fuzz"
seconds="${FUZZ_SECONDS:-15}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_COMPILER=clang++ \
  -DISOCORR_FUZZ=ON -DISOCORR_SANITIZE=address,undefined -DISOCORR_BUILD_TESTS=OFF -DISOCORR_BUILD_SERVICE=OFF \
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

mkdir -p "$build/findings"
failed=()
for target in "${targets[@]}"; do
  [ -n "${seed_dirs[$target]:-}" ] || { echo "fuzz: unknown target $target" >&2; exit 2; }
  corpus="$build/corpus/$target"  # grows across local runs; CI starts from the seeds
  mkdir -p "$corpus"
  inputs=("$corpus")
  for d in ${seed_dirs[$target]}; do inputs+=("$build/seeds/$d" "$here/fuzz/seeds/$d"); done
  echo "fuzz: $target for ${seconds}s"
  # One input may take 10 s and 512 MB in one allocation, 2 GB in all; more is a finding.
  if ! "$build/fuzz/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=512 \
        -detect_leaks=1 -print_final_stats=1 -artifact_prefix="$build/findings/$target-" "${inputs[@]}" \
        >"$build/findings/$target.log" 2>&1; then
    failed+=("$target")
    tail -n 60 "$build/findings/$target.log"
  fi
  grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb)' "$build/findings/$target.log" | tr '\n' ' '
  echo
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs in $build/findings/)" >&2
  exit 1
fi
echo "fuzz: all ${#targets[@]} targets clean"
