#!/usr/bin/env bash
# Session round trips per second over REST and WebSocket (bench/api_bench.cpp) against a server this
# script starts on a free port with a temporary database.
#   usage: bench/api_bench.sh [build dir=build/release] [seconds per case=5] [case]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
seconds=${2:-5}
dir=$(mktemp -d)
trap 'kill "$pid" 2>/dev/null; rm -rf "$dir"' EXIT
"$build/server/app/hrisim" serve --port 0 --db "$dir/bench.db" --log-requests 0 >"$dir/out" &
pid=$!
for _ in $(seq 100); do grep -q listening "$dir/out" && break; sleep 0.1; done
port=$(sed -n 's/.*listening on http:\/\/[^:]*:\([0-9]*\).*/\1/p' "$dir/out")
"$build/bench/api_bench" "$port" "$seconds" ${3:+"$3"}
