#!/usr/bin/env bash
# Pack-time benchmark: the sample's states/ and a generated set of N pipelines (each with its own
# shaders, so every one is compiled), with 1 thread and with every core. Prints a Markdown table.
# Usage: pack_benchmark.sh <statepack> <repository root> [N=300] [repeats=3]
# Run it through CMake: cmake --build build --target bench_pack
set -euo pipefail
statepack=$1 root=$2 count=${3:-300} repeats=${4:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cores=$(nproc)

bash "$(dirname "$0")/generate_pipelines.sh" "$root" "$work/gen" "$count"

# Median wall time in milliseconds of `repeats` runs of a pack.
median_ms() {
  local times=()
  for ((r = 0; r < repeats; r++)); do
    local start end
    start=$(date +%s%N)
    "$statepack" pack "$@" -o "$work/out.spk" --vulkan > /dev/null
    end=$(date +%s%N)
    times+=($(((end - start) / 1000000)))
  done
  printf '%s\n' "${times[@]}" | sort -n | sed -n "$(((repeats + 1) / 2))p"
}

sample_inputs=()
for f in "$root"/states/*.json; do sample_inputs+=(-i "$f"); done
echo "statepack pack time, median of $repeats runs, $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'))"
echo
echo "| input | pipelines | distinct shaders | -t 1 (ms) | -t $cores (ms) | speed-up |"
echo "|---|---|---|---|---|---|"
row() {
  local name=$1 pipelines=$2 shaders=$3
  shift 3
  local one all
  one=$(median_ms -t 1 "$@")
  all=$(median_ms -t "$cores" "$@")
  echo "| $name | $pipelines | $shaders | $one | $all | $(awk -v a="$one" -v b="$all" 'BEGIN { printf "%.2fx", a / b }') |"
}
contents=$("$statepack" pack "${sample_inputs[@]}" -s "$root/shaders" -o "$work/s.spk" --vulkan --print_contents)
sample_pipelines=$(echo "$contents" | grep -c "^pipeline '")
sample_shaders=$(echo "$contents" | sed -n "s/^\([0-9]*\) SPIR-V blob.*/\1/p")
row "states/ (sample)" "$sample_pipelines" "$sample_shaders" "${sample_inputs[@]}" -s "$root/shaders"
row "generated" "$count" "$((count + 1))" -i "$work/gen/generated.json"
