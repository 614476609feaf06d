#!/usr/bin/env bash
# Builds the test suite under sanitizers and runs it. Every process the tests start (the
# CLI, the server) is instrumented too; their reports go to files, and any report fails.
#   scripts/sanitize.sh asan   ASan + UBSan (gcc), build-asan/
#   scripts/sanitize.sh tsan   TSan (gcc), build-tsan/: core and the job scheduler, in process
# Both run the suite but the end-to-end tests on the real benchmark data (about 50 s in
# Release, 6 to 20 times that under the sanitizers: most of CI's time; scripts/test.sh runs
# them); their code paths are the ones the synthetic tests drive. TSan also leaves out the
# CLI's match tests (the same threaded pipeline as MatcherOnBlob, at several times its cost),
# the thread-count comparison (the pipeline once more on one thread: over 10 minutes) and the
# single-threaded cleaning speed test, whose 1 s budget TSan's slowdown exceeds, and the
# tests that start the server and CLI processes (Service, ApiLimits, Faults, Observability,
# Replicas): there TSan
# reports races inside gRPC's inline headers and threads (byte_buffer.h, callback
# handlers' std::function, grpc_core::Thread) that Debian's uninstrumented gRPC makes
# invisible to it, seen in 1 CI run of 2; suppressing them would need patterns broad
# enough to hide our own handlers' races. The scheduler is raced in process instead
# (JobManager tests), so TSan covers core and the job scheduler as issue 10 asks.
# Extra arguments go to ctest (e.g. -R Mesh).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
kind="${1:?usage: scripts/sanitize.sh asan|tsan [ctest args]}"
shift
skipped='RealData|GroundTruthRealData'
case "$kind" in
  asan) sanitizers=address,undefined ;;
  tsan) sanitizers=thread; skipped="$skipped|MatchCommand|MatcherOnBlob[.]ResultDoesNotDependOnThreadCount"
        skipped="$skipped|MeshCleaning[.]CleansSixtyThousandVerticesQuickly|Service|ApiLimits|Faults|Observability|Replicas" ;;
  *) echo "sanitize: unknown kind '$kind' (asan or tsan)" >&2; exit 2 ;;
esac
build="$here/build-$kind"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DISOCORR_SANITIZE="$sanitizers" \
  "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$(nproc)"

reports="$build/sanitizer-reports"
rm -rf "$reports"
mkdir -p "$reports"
suppressions="$here/tests/sanitizers"
common="log_path=$reports/report:print_stacktrace=1"
export ASAN_OPTIONS="$common:detect_leaks=1:strict_string_checks=1"
export LSAN_OPTIONS="$common:suppressions=$suppressions/lsan.supp"
export UBSAN_OPTIONS="$common:halt_on_error=1"
export TSAN_OPTIONS="$common:halt_on_error=1:second_deadlock_stack=1:suppressions=$suppressions/tsan.supp"

status=0
(cd "$build" && ctest --output-on-failure -j "$(nproc)" -E "^($skipped)([.]|$)" "$@") || status=$?
if compgen -G "$reports/report*" >/dev/null; then
  echo "sanitize: $kind reports:" >&2
  cat "$reports"/report* >&2
  status=1
fi
[ "$status" -eq 0 ] && echo "sanitize: $kind clean"
exit "$status"
