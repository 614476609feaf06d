#!/usr/bin/env bash
# Throughput of isocorr-server replicas sharing one PostgreSQL store (--store): the same
# JOBS matching jobs (the bundled example pair) with 1 and then 2 replicas, each run on a
# fresh database and freshly started replicas (cold shape caches), jobs submitted round
# robin through the replicas. Prints one line per run. A benchmark, never a test: on a
# small machine the replicas share its cores, so expect little scaling there.
#   tools/replica-throughput.sh [JOBS]        (default 6; uses build/ and Debian's postgresql)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${ISOCORR_BUILD_DIR:-$here/build}"
jobs="${1:-6}"
pg_bin="$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)"
[ -x "$pg_bin/initdb" ] || { echo "replica-throughput: needs Debian's postgresql package" >&2; exit 2; }
client="$build/client/isocorr"

work="$(mktemp -d)"
owner=()
if [ "$(id -u)" -eq 0 ]; then  # initdb and postgres refuse root
  chown nobody "$work"
  owner=(runuser -u nobody --)
fi
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
url_of() { echo "postgresql://isocorr@127.0.0.1:$port/$1"; }
servers=()
cleanup() {
  for pid in "${servers[@]}"; do kill "$pid" 2>/dev/null || true; done
  "${owner[@]}" "$pg_bin/pg_ctl" -D "$work/pg" -m immediate -w stop >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
"${owner[@]}" "$pg_bin/initdb" -D "$work/pg" -U isocorr --auth=trust --no-sync >/dev/null
"${owner[@]}" "$pg_bin/pg_ctl" -D "$work/pg" -l "$work/pg.log" -w \
  -o "-p $port -k $work -c listen_addresses=127.0.0.1" start >/dev/null
"$build/tools/isocorr-make-examples" "$work/examples" >/dev/null
source_mesh="$work/examples/meshes/creature.ply" target_mesh="$work/examples/meshes/creature_moved.ply"

for replicas in 1 2; do
  database="throughput_$replicas"
  "$pg_bin/psql" "$(url_of postgres)" -q -c "CREATE DATABASE $database"
  servers=() addresses=()
  for ((i = 0; i < replicas; i++)); do
    port_file="$work/$database-$i.port"
    "$build/server/isocorr-server" --listen 127.0.0.1:0 --port-file "$port_file" --data-dir "$work/$database-$i" \
      --store "$(url_of "$database")" --replica-id "replica-$i" --log-level warn 2>>"$work/servers.log" &
    servers+=("$!")
    for _ in $(seq 600); do [ -s "$port_file" ] && break; sleep 0.05; done
    addresses+=("127.0.0.1:$(cat "$port_file")")
  done
  "$client" --server "${addresses[0]}" upload "$source_mesh" "$target_mesh" >/dev/null
  started=$(date +%s.%N)
  names=()
  for ((j = 0; j < jobs; j++)); do
    names+=("$("$client" --server "${addresses[$((j % replicas))]}" submit "$source_mesh" "$target_mesh")")
  done
  for name in "${names[@]}"; do
    "$client" --server "${addresses[0]}" wait "$name" --timeout 3600 >/dev/null
  done
  ended=$(date +%s.%N)
  awk -v r="$replicas" -v n="$jobs" -v s="$started" -v e="$ended" \
    'BEGIN { printf "%d replica(s): %d jobs in %.1f s, %.2f jobs/min\n", r, n, e - s, 60 * n / (e - s) }'
  for pid in "${servers[@]}"; do kill "$pid"; wait "$pid" || true; done
  servers=()
done
