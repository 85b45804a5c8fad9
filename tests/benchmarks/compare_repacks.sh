#!/usr/bin/env bash
# Two statepack builds compared on the same repacks, run by run: a project of N shader files
# (generate_shader_project.sh, small or real), one cache shared by both, and each build's input stamps
# made first by a repack of nothing changed with every file older than the racy window (the record and
# stamps of a build are its own: archive_slot covers statepack's code, so a build that never made them
# repacks without its early start). Then, alternating A and B: one shader changed and repacked, `runs`
# times each; then, stamped again, repacks of nothing changed. A host whose speed changes from minute to minute slows both alike; prints each build's
# sorted times and median, for a one-changed repack and for a repack of nothing changed.
# `fresh` instead of `settled` leaves out the stamps made first: each build's one-changed repacks then
# follow a cold pack of files just written, as an edit loop on a new cache does (every repack follows
# its edit by less than the racy window).
# Usage: compare_repacks.sh <statepack A> <statepack B> <repository root> [N=1000] [runs=16] [small|real]
#        [settled|fresh]
set -euo pipefail
a=$1 b=$2 root=$3 count=${4:-1000} runs=${5:-16} kind=${6:-small} start=${7:-settled}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Each figure is timed by timed_run.c (the command's own start, run and exit; see there why).
timed_run=$work/timed_run
cc -O2 -o "$timed_run" "$(dirname "$0")/timed_run.c"
bash "$(dirname "$0")/generate_shader_project.sh" "$root" "$work/project" "$count" "$kind"
cd "$work/project"

# Wall milliseconds of one repack with build $1; sets $ms.
repack() {
  local code
  read -r ms _ code < <("$timed_run" "$1" pack -i project.json -o out.spk --vulkan --cache-dir cache)
  ((code == 0)) || { echo "FAIL: $1 pack exited with $code"; exit 1; }
}
sorted() { printf '%s\n' "$@" | sort -n | tr '\n' ' '; }
median() { printf '%s\n' "$@" | sort -n | sed -n "$((($# + 1) / 2))p"; }

for build in "$a" "$b"; do repack "$build"; done  # cold: the compiles (shared) and each build's record
if [[ $start == settled ]]; then
  sleep 2.2                                         # every input older than the racy window (2 s)
  for build in "$a" "$b"; do repack "$build"; done  # each build's stamps
fi
changed_a=() changed_b=() warm_a=() warm_b=()
for ((r = 0; r < runs; r++)); do
  for side in 0 1; do  # (a text neither build has compiled: a compile for each)
    sed -i "s/== \([0-9]*\)u) return;  \/\/ copy 0\$/== $((3000000 + r * 2 + side))u) return;  \/\/ copy 0/" \
      shader_0.comp
    if ((side == 0)); then
      repack "$a"
      changed_a+=("$ms")
    else
      repack "$b"
      changed_b+=("$ms")
    fi
  done
done
sleep 2.2
for build in "$a" "$b"; do repack "$build"; done  # each build's stamps of the last change
for ((r = 0; r < runs; r++)); do
  repack "$a"
  warm_a+=("$ms")
  repack "$b"
  warm_b+=("$ms")
done
echo "$count $kind shader files, $runs runs each, alternating, stamps $start at the start; ms, sorted (median)"
echo "one changed, A: $(sorted "${changed_a[@]}")($(median "${changed_a[@]}"))"
echo "one changed, B: $(sorted "${changed_b[@]}")($(median "${changed_b[@]}"))"
echo "nothing changed, A: $(sorted "${warm_a[@]}")($(median "${warm_a[@]}"))"
echo "nothing changed, B: $(sorted "${warm_b[@]}")($(median "${warm_b[@]}"))"
