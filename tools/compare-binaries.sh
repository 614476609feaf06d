#!/usr/bin/env bash
# Two builds of `isocorr` timed against each other on a dataset's pairs, interleaved pair by
# pair, with their maps compared byte for byte. On the shared 2-core VMs we develop on, the
# same binary's time swings by 20% within an hour, so a speed change is only visible when
# the old and the new binary run side by side in time; and a change meant to be exact is
# only exact if every map is identical. A benchmark, never a test.
#   tools/compare-binaries.sh OLD_ISOCORR NEW_ISOCORR DATASET [EVERY] [-- MATCH_FLAGS...]
# DATASET is a folder under ../shared/data (or ISOCORR_DATA) with a pairs.tsv; EVERY takes
# every EVERY-th pair (default 1). The two binaries alternate which goes first, so a drift of
# the machine's speed within a pair falls on both. Prints one line per pair and a summary;
# exits 1 when any map differs.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
if [ $# -lt 3 ]; then
  sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
old="$1" new="$2" dataset="$3"
shift 3
every=1
if [ $# -gt 0 ] && [ "$1" != "--" ]; then every="$1"; shift; fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
flags=("$@")
data="${ISOCORR_DATA:-$here/../shared/data}/$dataset"
[ -f "$data/pairs.tsv" ] || { echo "compare-binaries: no $data/pairs.tsv" >&2; exit 2; }
for binary in "$old" "$new"; do
  [ -x "$binary" ] || { echo "compare-binaries: $binary is not an executable" >&2; exit 2; }
done
case "$every" in '' | *[!0-9]* | 0) echo "compare-binaries: EVERY must be a positive whole number" >&2; exit 2 ;; esac

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# One match, its map left in $work/$2.map and its wall and CPU (user + system) seconds in
# $work/$2.seconds. CPU time shows a change in work where the VM's drift hides it in wall time.
run() {
  local binary="$1" name="$2" source="$3" target="$4" TIMEFORMAT='%R %U %S'
  { time "$binary" match "$data/$source" "$data/$target" -o "$work/$name.map" "${flags[@]}" >/dev/null 2>"$work/$name.log"; } \
    2>"$work/$name.time" ||
    { echo "compare-binaries: $binary failed on $source -> $target:" >&2; cat "$work/$name.log" >&2; exit 1; }
  awk '{ printf "%.3f %.3f\n", $1, $2 + $3 }' "$work/$name.time" >"$work/$name.seconds"
}

index=0 pairs=0 differing=0
while IFS=$'\t' read -r source target _; do
  [ "$source" = "source" ] && continue  # the header
  index=$((index + 1))
  [ $(((index - 1) % every)) -eq 0 ] || continue
  if [ $((pairs % 2)) -eq 0 ]; then
    run "$old" old "$source" "$target"
    run "$new" new "$source" "$target"
  else
    run "$new" new "$source" "$target"
    run "$old" old "$source" "$target"
  fi
  read -r old_seconds old_cpu <"$work/old.seconds"
  read -r new_seconds new_cpu <"$work/new.seconds"
  pairs=$((pairs + 1))
  if cmp -s "$work/old.map" "$work/new.map"; then same="same map"; else same="MAPS DIFFER"; differing=$((differing + 1)); fi
  echo "$old_seconds $new_seconds $old_cpu $new_cpu" >>"$work/seconds"
  printf '%-40s old %6.2f s (CPU %6.2f)  new %6.2f s (CPU %6.2f)  %s\n' "$(basename "$source") -> $(basename "$target")" \
    "$old_seconds" "$old_cpu" "$new_seconds" "$new_cpu" "$same"
done <"$data/pairs.tsv"

[ "$pairs" -gt 0 ] || { echo "compare-binaries: no pairs in $data/pairs.tsv" >&2; exit 2; }
awk -v set="$dataset" -v differ="$differing" '{ old += $1; new += $2; old_cpu += $3; new_cpu += $4 } END {
  printf "== %s: %d pairs, old %.2f s per pair, new %.2f s per pair (new/old %.3f), %d maps differ\n",
    set, NR, old / NR, new / NR, new / old, differ
  printf "   CPU seconds per pair: old %.2f, new %.2f (new/old %.3f)\n", old_cpu / NR, new_cpu / NR, new_cpu / old_cpu }' "$work/seconds"
[ "$differing" -eq 0 ]
