#!/usr/bin/env bash
# Requests per second and latency of `hrisim serve` on loopback, measured with wrk (installed from
# Debian if missing). Starts its own server on a free port with a temporary database.
#   usage: bench/http_bench.sh [build dir=build/release] [seconds=10] [connections=32]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
seconds=${2:-10}
connections=${3:-32}
command -v wrk >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -q wrk >/dev/null
dir=$(mktemp -d)
trap 'kill "$pid" 2>/dev/null; rm -rf "$dir"' EXIT
"$build/server/app/hrisim" serve --port 0 --db "$dir/bench.db" --log-requests 0 >"$dir/out" &
pid=$!
for _ in $(seq 100); do grep -q listening "$dir/out" && break; sleep 0.1; done
port=$(sed -n 's/.*listening on http:\/\/[^:]*:\([0-9]*\).*/\1/p' "$dir/out")
for path in /healthz /api/v1/version /; do
  echo "== GET $path, $connections connections, 2 threads, ${seconds}s"
  wrk -t2 -c"$connections" -d"${seconds}s" --latency "http://127.0.0.1:$port$path" | grep -E "Requests/sec|^ +50%|^ +99%|Socket errors|Non-2xx"
done
