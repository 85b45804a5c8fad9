#!/usr/bin/env bash
# A long fuzzing run for the figures in docs/fuzzing.md: 10 million executions (FUZZ_RUNS to change)
# from the given seeds, then one summary line with the executions, the time and the speed.
# Usage: run_long.sh <fuzzer> <work dir> [fuzzer flag] -- <seed file>...
set -euo pipefail
fuzzer=$1 work=$2 flag=$3; shift 3
[[ "${1:-}" == "--" ]] && shift
runs=${FUZZ_RUNS:-10000000}
rm -rf "$work" && mkdir -p "$work"
i=0
for seed in "$@"; do cp "$seed" "$work/seed-$i-$(basename "$seed")"; i=$((i + 1)); done
start=$(date +%s.%N)
"$fuzzer" -runs="$runs" -seed=1 -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 ${flag:+"$flag"} "$work" \
  2> "$work.log" || { tail -50 "$work.log"; exit 1; }
end=$(date +%s.%N)
grep -E "stat::number_of_executed_units|stat::peak_rss_mb|cov:" "$work.log" | tail -3
awk -v s="$start" -v e="$end" -v r="$runs" -v f="$(basename "$fuzzer")" \
  'BEGIN { printf "%s: %d executions in %.0f s (%.0f exec/s), no crash\n", f, r, e - s, r / (e - s) }'
