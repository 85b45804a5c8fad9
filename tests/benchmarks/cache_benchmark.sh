#!/usr/bin/env bash
# The compile cache (pack --cache-dir) on a project of N shader files (generate_shader_project.sh, real or
# small shaders):
# a pack without a cache, a cold pack into an empty cache, a warm pack with nothing changed, and a pack
# after one shader file changed, each with every core; prints a Markdown table with each figure's share
# of the cold pack, and checks that every archive is the bytes of a pack without a cache.
# Usage: cache_benchmark.sh <statepack> <repository root> [N=1000] [repeats=3] [real|small]
# Run it through CMake: cmake --build build --target bench_cache (both kinds)
set -euo pipefail
statepack=$1 root=$2 count=${3:-1000} repeats=${4:-3} kind=${5:-real}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Each figure is timed by timed_run.c (the command's own start, run and exit; see there why).
timed_run=$work/timed_run
cc -O2 -o "$timed_run" "$(dirname "$0")/timed_run.c"
bash "$(dirname "$0")/generate_shader_project.sh" "$root" "$work/project" "$count" "$kind"
cd "$work/project"

# Wall milliseconds and peak RSS (MiB) of one pack of project.json; sets $ms and $mib.
pack() {
  local out=$1 kib code
  shift
  read -r ms kib code < <("$timed_run" "$statepack" pack -i project.json -o "$out" --vulkan "$@")
  ((code == 0)) || { echo "FAIL: statepack pack -o $out $* exited with $code"; exit 1; }
  mib=$((kib / 1024))
}
# The median of the arguments.
median() { printf '%s\n' "$@" | sort -n | sed -n "$((($# + 1) / 2))p"; }

# Without a cache and cold, interleaved run by run (this machine's load varies from minute to minute).
plain=() cold=()
for ((r = 0; r < repeats; r++)); do
  pack plain.spk
  plain+=("$ms") plain_mib=$mib
  rm -rf cache
  pack cold.spk --cache-dir cache
  cold+=("$ms") cold_mib=$mib
done
plain_ms=$(median "${plain[@]}") cold_ms=$(median "${cold[@]}")
warm=() changed=()
for ((r = 0; r < repeats; r++)); do
  pack warm.spk --cache-dir cache
  warm+=("$ms") warm_mib=$mib
done
for archive in cold.spk warm.spk; do cmp -s plain.spk "$archive" || { echo "FAIL: $archive differs from a pack without a cache"; exit 1; }; done
for ((r = 0; r < repeats; r++)); do
  # One shader changed (its early-return constant), as an edit does; each repeat changes it again.
  sed -i "s/== \([0-9]*\)u) return;  \/\/ copy 0\$/== $((2000000 + r))u) return;  \/\/ copy 0/" shader_0.comp
  pack changed.spk --cache-dir cache
  changed+=("$ms") changed_mib=$mib
done
pack reference.spk  # the last change, without a cache
cmp -s reference.spk changed.spk || { echo "FAIL: changed.spk differs from a pack without a cache"; exit 1; }
# The floor of a repack in a new process that compiles anything: a pack of one of these shaders alone,
# without a cache (the process's start, glslang's built-in tables, one compile, an archive written).
echo '{"Pipelines": [{"PSODesc": {"Name": "One"}, "pCS": {"Desc": {"Name": "One CS"}, "FilePath": "shader_1.comp"}}]}' \
  > one.json
floor=()
for ((r = 0; r < repeats; r++)); do
  read -r ms _ code < <("$timed_run" "$statepack" pack -i one.json -o one.spk --vulkan)
  ((code == 0)) || { echo "FAIL: statepack pack -i one.json exited with $code"; exit 1; }
  floor+=("$ms")
done

# The same edit under --watch: one process kept between packs (glslang initialised, and what the last pack
# read and made kept while it holds: repack_memo.hpp), each repack's time as the watch prints it, from
# the change seen (no quiet period) to the archive written; the last archive checked like the others.
watch_log=$work/watch.log
/usr/bin/time -f '%M' -o "$work/watch_rss" "$statepack" pack -i project.json -o watched.spk --vulkan \
  --cache-dir cache --watch --watch-quiet-ms 0 > "$watch_log" 2>&1 &
watch_pid=$!
# Waits until the watch has printed `count` lines starting with `prefix`.
wait_for() {
  local count=$1 prefix=$2
  for ((t = 0; t < 1200; t++)); do
    (($(grep -c "^$prefix" "$watch_log" || true) >= count)) && return 0
    grep -q "^pack failed" "$watch_log" && break
    sleep 0.05
  done
  echo "FAIL: --watch did not print '$prefix' $count time(s):"
  cat "$watch_log"
  pkill -P "$watch_pid"
  exit 1
}
wait_for 1 "packed "
watched=()
for ((r = 0; r < 3 * repeats; r++)); do
  sed -i "s/== \([0-9]*\)u) return;  \/\/ copy 0\$/== $((4000000 + r))u) return;  \/\/ copy 0/" shader_0.comp
  wait_for $((r + 1)) "repacked "
  watched+=("$(sed -n 's/^repacked watched.spk in \([0-9.]*\) s.*/\1/p' "$watch_log" | tail -1 |
    awk '{ printf "%d", $1 * 1000 }')")
done
pkill -INT -P "$watch_pid"  # (the watch under time(1), which ignores SIGINT itself)
wait "$watch_pid"
watch_mib=$(($(cat "$work/watch_rss") / 1024))
pack reference.spk
cmp -s reference.spk watched.spk || { echo "FAIL: the watch's archive differs from a pack without a cache"; exit 1; }
warm_ms=$(median "${warm[@]}") changed_ms=$(median "${changed[@]}") watched_ms=$(median "${watched[@]}")
share() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f %%", 100 * a / b }'; }
if [[ $kind == real ]]; then
  what="the path tracer's compute shader, ~480 lines with its #includes, each copy compiling to its own module"
else
  what="small compute shaders of ten lines, each compiling to its own module"
fi
echo "statepack pack --cache-dir, $count shader files ($what), -t $(nproc),"
echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')"
echo "medians of $repeats runs (without a cache: ${plain[*]}; cold: ${cold[*]}; warm: ${warm[*]}; one changed:"
echo "${changed[*]}; under --watch: ${watched[*]} ms); every archive byte-identical to a pack without a cache"
echo
echo "| pack | wall (ms) | share of a pack without a cache | share of cold | peak RSS (MiB) |"
echo "|---|---|---|---|---|"
echo "| without a cache | $plain_ms | 100.0 % | $(share "$plain_ms" "$cold_ms") | $plain_mib |"
echo "| cold (empty cache) | $cold_ms | $(share "$cold_ms" "$plain_ms") | 100.0 % | $cold_mib |"
echo "| warm (nothing changed) | $warm_ms | $(share "$warm_ms" "$plain_ms") | $(share "$warm_ms" "$cold_ms") | $warm_mib |"
echo "| one of $count shaders changed | $changed_ms | $(share "$changed_ms" "$plain_ms") | $(share "$changed_ms" "$cold_ms") | $changed_mib |"
echo "| one changed, under --watch | $watched_ms | $(share "$watched_ms" "$plain_ms") | $(share "$watched_ms" "$cold_ms") | $watch_mib (the watch's peak) |"
floor_ms=$(median "${floor[@]}")
echo
echo "A new process that compiles one of these shaders alone (its start, glslang's built-in tables, one"
echo "compile, an archive written; ${floor[*]} ms): $floor_ms ms, $(share "$floor_ms" "$cold_ms") of cold: no"
echo "repack in a new process that compiles a shader can take less (--watch keeps one process)."
