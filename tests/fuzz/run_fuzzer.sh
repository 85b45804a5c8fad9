#!/usr/bin/env bash
# Runs a fuzzer for a bounded time on a fresh corpus seeded with the given files.
# Usage: run_fuzzer.sh <fuzzer> <work dir> <seconds> [fuzzer flags...] -- <seed file>...
set -euo pipefail
fuzzer=$1 work=$2 seconds=$3; shift 3
flags=()
while [[ $# -gt 0 && "$1" != "--" ]]; do flags+=("$1"); shift; done
[[ $# -gt 0 ]] && shift
rm -rf "$work" && mkdir -p "$work"
i=0
for seed in "$@"; do cp "$seed" "$work/seed-$i-$(basename "$seed")"; i=$((i + 1)); done
exec "$fuzzer" -max_total_time="$seconds" -seed=1 -rss_limit_mb=2048 -max_len=16384 "${flags[@]}" "$work"
