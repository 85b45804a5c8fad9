#!/usr/bin/env bash
# Pack-time benchmark, printed as Markdown tables:
# 1. one thread against every core, on the sample's states/, 300 generated pipelines with tiny shaders
#    (generate_pipelines.sh) and 300 real-sized shaders (generate_shader_project.sh: the path tracer's
#    compute shader, each copy its own module). The runs of -t 1 and -t <cores> alternate, `repeats`
#    times, so a machine whose load changes from minute to minute slows both alike; each column gives
#    the minimum and the median. A pack of one trivial shader is timed the same way: process start and
#    glslang's one-time initialisation of its built-in symbol tables (a global lock in glslang, serial
#    by nature), the fixed cost no thread count changes; a column gives the speed-up of the rest, and
#    the last one the most -t <cores> could give with that fixed cost serial and the rest split evenly
#    (Amdahl's bound: -t 1 median / (fixed + (-t 1 median - fixed) / cores)).
# 2. scaling: 10,000 and 100,000 compute pipelines sharing one shader, wall time and peak RSS.
# Usage: pack_benchmark.sh <statepack> <repository root> [N=300] [repeats=5]
# Run it through CMake: cmake --build build --target bench_pack
set -euo pipefail
statepack=$1 root=$2 count=${3:-300} repeats=${4:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Each figure is timed by timed_run.c (the command's own start, run and exit; see there why).
timed_run=$work/timed_run
cc -O2 -o "$timed_run" "$(dirname "$0")/timed_run.c"
cores=$(nproc)
here=$(dirname "$0")

bash "$here/generate_pipelines.sh" "$root" "$work/gen" "$count"
bash "$here/generate_shader_project.sh" "$root" "$work/real" "$count"
mkdir -p "$work/one"
cp "$root/shaders/fill_buffer.comp" "$work/one/"
echo '{"Pipelines": [{"PSODesc": {"Name": "One"}, "pCS": {"Desc": {"Name": "One CS"}, "FilePath": "fill_buffer.comp"}}]}' \
  > "$work/one/one.json"

# Wall milliseconds of one pack; sets $ms (and $kib, the peak RSS).
pack_ms() {
  local code
  read -r ms kib code < <("$timed_run" "$statepack" pack "$@" -o "$work/out.spk" --vulkan)
  ((code == 0)) || { echo "FAIL: statepack pack $* exited with $code"; exit 1; }
}
min() { printf '%s\n' "$@" | sort -n | head -1; }
median() { printf '%s\n' "$@" | sort -n | sed -n "$((($# + 1) / 2))p"; }

# Alternating -t 1 / -t <cores> runs; sets one_min one_med all_min all_med.
measure() {
  local one=() all=()
  for ((r = 0; r < repeats; r++)); do
    pack_ms -t 1 "$@"
    one+=("$ms")
    pack_ms -t "$cores" "$@"
    all+=("$ms")
  done
  one_min=$(min "${one[@]}") one_med=$(median "${one[@]}")
  all_min=$(min "${all[@]}") all_med=$(median "${all[@]}")
}

measure -i "$work/one/one.json"
fixed=$one_med
echo "statepack pack, $cores cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')), -t 1 and -t $cores"
echo "alternating, $repeats runs each; fixed cost (one trivial shader, -t 1 median): $fixed ms"
echo
echo "| input | pipelines | distinct shaders | -t 1 min / median (ms) | -t $cores min / median (ms) | speed-up (medians) | speed-up beyond the fixed cost | most -t $cores could give, the fixed cost serial |"
echo "|---|---|---|---|---|---|---|---|"
row() {
  local name=$1 pipelines=$2 shaders=$3
  shift 3
  measure "$@"
  echo "| $name | $pipelines | $shaders | $one_min / $one_med | $all_min / $all_med |" \
       "$(awk -v a="$one_med" -v b="$all_med" 'BEGIN { printf "%.2fx", a / b }') |" \
       "$(awk -v a="$one_med" -v b="$all_med" -v f="$fixed" 'BEGIN { printf "%.2fx", (a - f) / (b - f) }') |" \
       "$(awk -v a="$one_med" -v f="$fixed" -v c="$cores" 'BEGIN { printf "%.2fx", a / (f + (a - f) / c) }') |"
}
sample_inputs=()
for f in "$root"/states/*.json; do sample_inputs+=(-i "$f"); done
contents=$("$statepack" pack "${sample_inputs[@]}" -s "$root/shaders" -o "$work/s.spk" --vulkan --print_contents)
sample_pipelines=$(echo "$contents" | grep -c "^pipeline '")
sample_shaders=$(echo "$contents" | sed -n "s/^\([0-9]*\) SPIR-V blob.*/\1/p")
row "states/ (sample)" "$sample_pipelines" "$sample_shaders" "${sample_inputs[@]}" -s "$root/shaders"
row "generated, tiny shaders" "$count" "$((count + 1))" -i "$work/gen/generated.json"
row "generated, real-sized shaders" "$count" "$count" -i "$work/real/project.json"

# Scaling: many pipelines over one shader (the notation, layout, archive and load-back stages).
echo
echo "| compute pipelines sharing one shader | -t $cores wall (ms) | peak RSS (MiB) |"
echo "|---|---|---|"
for n in 10000 100000; do
  python3 - "$n" "$work/scale_$n.json" << 'EOF'
import sys
n, path = int(sys.argv[1]), sys.argv[2]
with open(path, "w") as f:
    f.write('{"Pipelines": [\n')
    f.write(",\n".join('{"PSODesc": {"Name": "Compute %d"}, "pCS": {"Desc": {"Name": "CS"}, "FilePath": "fill_buffer.comp"}}' % i
                       for i in range(n)))
    f.write("\n]}\n")
EOF
  cp "$root/shaders/fill_buffer.comp" "$work/"
  times=()
  for ((r = 0; r < 3; r++)); do
    pack_ms -i "$work/scale_$n.json"
    times+=("$ms")
  done
  echo "| $n | $(median "${times[@]}") (runs: ${times[*]}) | $((kib / 1024)) |"
done
