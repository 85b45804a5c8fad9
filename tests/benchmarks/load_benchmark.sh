#!/usr/bin/env bash
# Load benchmark and binary sizes. Packs the sample's states/ and 100 generated pipelines, times
# archive bytes -> pipelines against bare Vulkan and against run-time glslang, then compares the
# stripped sizes of two minimal programs: one with the dearchiver, one with glslang.
# Usage: load_benchmark.sh <bin dir> <repository root> [repeats=31]
# Run it through CMake: cmake --build build --target bench_load
set -euo pipefail
bin=$1 root=$2 repeats=${3:-31}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
here=$(cd "$(dirname "$0")" && pwd)
bash "$here/generate_pipelines.sh" "$root" "$work/gen" 100
"$bin/statepack" pack -i "$root/states/slice.json" -s "$root/shaders" -o "$work/states.spk" --vulkan
"$bin/statepack" pack -i "$work/gen/generated.json" -o "$work/generated.spk" --vulkan
device=$(vulkaninfo --summary 2>/dev/null | grep -m1 deviceName | cut -d= -f2 | sed 's/^ *//')
echo "Load time, $repeats runs alternating with bare Vulkan, on ${device:-the first Vulkan device} ($(nproc) cores)"
echo
"$bin/load_benchmark" "$work/states.spk" "$root/states/slice.json" "$root/shaders" "$repeats"
STATEPACK_BENCH_BREAKDOWN=1 "$bin/load_benchmark" "$work/generated.spk" "$work/gen/generated.json" "$work/gen" "$repeats" | tail -5
echo
# Times on a shared machine drift by more than the overhead measured; instruction counts do not. Each
# path runs alone under callgrind, five runs counted (after one uncounted), twice, so that the two
# counts show how far runs agree.
count_instructions() {  # <bare|statepack> <out file>
  STATEPACK_BENCH_ONLY=$1 valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$2" \
    "$bin/load_benchmark" "$work/generated.spk" "$work/gen/generated.json" "$work/gen" 5 > /dev/null 2>&1
  awk '/^summary:/ { print $2 }' "$2"
}
if command -v valgrind > /dev/null; then
  echo "| instructions per load (callgrind, 5 runs) | bare Vulkan | statepack, 1 thread | statepack's own | overhead |"
  echo "|---|---|---|---|---|"
  for attempt in 1 2; do
    b=$(count_instructions bare "$work/bare.cg") s=$(count_instructions statepack "$work/statepack.cg")
    awk -v b="$b" -v s="$s" -v a="$attempt" 'BEGIN {
      printf "| generated.spk, count %d | %.0f | %.0f | %.0f | %+.2f %% |\n", a, b / 5, s / 5, (s - b) / 5, 100 * (s - b) / b }'
  done
else
  echo "(no instruction counts: valgrind is not installed; .ci/setup installs it)"
fi
echo
strip -o "$work/min_dearchiver" "$bin/min_dearchiver"
strip -o "$work/min_glslang" "$bin/min_glslang"
"$work/min_dearchiver" "$work/states.spk" "Fill Buffer PSO" > /dev/null
"$work/min_glslang" "$root/shaders/fill_buffer.comp" > /dev/null
d=$(stat -c %s "$work/min_dearchiver") g=$(stat -c %s "$work/min_glslang")
echo "| minimal program (stripped) | bytes |"
echo "|---|---|"
echo "| archive + libstatepack_dearchiver | $d |"
echo "| GLSL + glslang at run time | $g |"
echo "| ratio | $(awk -v a="$g" -v b="$d" 'BEGIN { printf "%.1fx smaller with the dearchiver", a / b }') |"
