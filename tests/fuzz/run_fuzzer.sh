#!/usr/bin/env bash
# Runs the archive fuzzer for a bounded time on a fresh corpus seeded with real archives.
# Usage: run_fuzzer.sh <fuzzer> <work dir> <seconds> <seed archive>...
set -euo pipefail
fuzzer=$1 work=$2 seconds=$3; shift 3
rm -rf "$work" && mkdir -p "$work"
cp "$@" "$work/"
exec "$fuzzer" -max_total_time="$seconds" -seed=1 -rss_limit_mb=2048 -max_len=16384 "$work"
