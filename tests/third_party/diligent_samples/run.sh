#!/usr/bin/env bash
# Packs the pipelines of Diligent Engine's tutorials (DiligentSamples/Tutorials) with statepack, from
# notation files written here from each tutorial's C++ (notation/*.json), plus Tutorial26_StateCache's
# own assets/RenderStates.json unchanged; each pipeline for Vulkan, for OpenGL, and `statepack verify`
# on the Vulkan archive. Prints one line per pipeline and a summary (see README.md).
# Not part of the CI suite: it needs a checkout of https://github.com/DiligentGraphics/DiligentSamples,
# and CI has no network. Nothing is written into the checkout: archives and logs go to a temporary folder.
#
# usage: tests/third_party/diligent_samples/run.sh /path/to/DiligentSamples-checkout [build-dir]
#   build-dir: this repository's build folder, holding bin/statepack (default: build)
# Environment:
#   DILIGENTFX_DIR     a DiligentFX checkout; its Shaders/ folders are shader directories of the tutorials
#                      whose C++ loads shaders through DiligentFX's shader source factory (Tutorial27).
#                      Unset: those tutorials are skipped (and listed as skipped).
#   EXTRA_SHADER_DIRS  more shader directories (':'-separated), given to every pack
#   STATEPACK_TIMEOUT  seconds one statepack run may take (default 600)
#   KEEP_OUTPUT=1      keep the temporary folder (archives, logs, split notation) and print its path
# Exit status: 0, or 1 if a statepack run crashed or timed out (exit status >= 124), 2 on usage error.
# Pipelines that fail to pack or verify do not change the exit status: the summary reports them.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 /path/to/DiligentSamples-checkout [build-dir]" >&2; exit 2
fi
[ -d "$1" ] || { echo "error: $1 is not a directory" >&2; exit 2; }
checkout=$(cd "$1" && pwd)
[ -f "$checkout/Tutorials/Tutorial26_StateCache/assets/RenderStates.json" ] || {
  echo "error: $checkout/Tutorials/Tutorial26_StateCache/assets/RenderStates.json not found: not a DiligentSamples checkout?" >&2; exit 2; }
build=${2:-$root/build}
statepack="$build/bin/statepack"
[ -x "$statepack" ] || { echo "error: $statepack not found or not executable (build the project, or give the build folder)" >&2; exit 2; }
statepack=$(cd "$(dirname "$statepack")" && pwd)/statepack
command -v python3 > /dev/null || { echo "error: python3 is needed" >&2; exit 2; }
timeout_s=${STATEPACK_TIMEOUT:-600}
case $timeout_s in ''|*[!0-9]*) echo "error: STATEPACK_TIMEOUT must be a number of seconds" >&2; exit 2;; esac

fx_dirs=()
if [ -n "${DILIGENTFX_DIR:-}" ]; then
  [ -d "$DILIGENTFX_DIR/Shaders" ] || { echo "error: DILIGENTFX_DIR=$DILIGENTFX_DIR has no Shaders folder: not a DiligentFX checkout?" >&2; exit 2; }
  # DiligentFX's shader source factory serves every file under Shaders/ by its bare name
  while IFS= read -r d; do fx_dirs+=("$d"); done < <(find "$(cd "$DILIGENTFX_DIR/Shaders" && pwd)" -type d | LC_ALL=C sort)
fi
extra_dirs=()
if [ -n "${EXTRA_SHADER_DIRS:-}" ]; then
  IFS=: read -r -a parts <<< "$EXTRA_SHADER_DIRS"
  for d in "${parts[@]}"; do
    [ -z "$d" ] && continue
    [ -d "$d" ] || { echo "error: EXTRA_SHADER_DIRS names $d, which is not a directory" >&2; exit 2; }
    extra_dirs+=("$(cd "$d" && pwd)")
  done
fi

OUT=$(mktemp -d)
if [ "${KEEP_OUTPUT:-0}" = 1 ]; then echo "output folder (kept): $OUT"; else trap 'rm -rf "$OUT"' EXIT; fi
results="$OUT/results.tsv"; : > "$results"
crashed=0

# Shader directories of a tutorial (-s options), as its C++ sets up its shader source factory.
# Prints nothing and returns 1 when the tutorial needs something not given.
shader_dirs() {  # TUTORIAL
  local t=$1 d
  printf '%s\n' -s "$checkout/Tutorials/$t/assets"
  case $t in
    Tutorial27_PostProcessing)
      # CreateDefaultShaderSourceStreamFactory("shaders") compounded with DiligentFX's factory
      printf '%s\n' -s "$checkout/Tutorials/$t/assets/shaders"
      [ ${#fx_dirs[@]} -gt 0 ] || return 1
      for d in "${fx_dirs[@]}"; do printf '%s\n' -s "$d"; done;;
  esac
  for d in "${extra_dirs[@]}"; do printf '%s\n' -s "$d"; done
}

run() {  # LOG CWD COMMAND... : runs it in CWD with the time limit, output to LOG; returns its exit status
  local log=$1 cwd=$2 rc=0; shift 2
  (cd "$cwd" && timeout "$timeout_s" "$@") > "$log" 2>&1 || rc=$?
  if [ "$rc" -ge 124 ]; then
    crashed=1
    echo "CRASH: exit status $rc (timeout or signal): $*" | tee -a "$log"
  fi
  return "$rc"
}

word() { if [ "$1" = 0 ]; then echo PASS; elif [ "$1" = - ]; then echo "-   "; else echo FAIL; fi; }

# Packs one pipeline's notation file for Vulkan and for OpenGL, verifies the Vulkan archive, records it.
check_pipeline() {  # TUTORIAL NAME JSON CWD LOGDIR DIR-OPTIONS...
  local tut=$1 name=$2 json=$3 cwd=$4 logdir=$5 vk=0 gl=0 ver=-; shift 5
  mkdir -p "$logdir"
  run "$logdir/vulkan.log" "$cwd" "$statepack" pack -i "$json" "$@" -o "$logdir/vulkan.spk" --vulkan || vk=$?
  run "$logdir/opengl.log" "$cwd" "$statepack" pack -i "$json" "$@" -o "$logdir/opengl.spk" --opengl || gl=$?
  if [ "$vk" = 0 ]; then
    ver=0; run "$logdir/verify.log" "$cwd" "$statepack" verify "$logdir/vulkan.spk" || ver=$?
  fi
  printf 'vulkan %s  opengl %s  verify %s  %s: %s\n' "$(word "$vk")" "$(word "$gl")" "$(word "$ver")" "$tut" "'$name'"
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$tut" "$name" "$vk" "$gl" "$ver" "$logdir" >> "$results"
}

echo "statepack: $statepack"
echo "checkout:  $checkout"
[ ${#fx_dirs[@]} -gt 0 ] && echo "DiligentFX shader folders: ${#fx_dirs[@]} under $DILIGENTFX_DIR/Shaders"
echo
skipped=()
mkdir -p "$OUT/work" "$OUT/split"
for notation in "$here"/notation/*.json; do
  tut=$(basename "$notation" .json)
  if [ ! -d "$checkout/Tutorials/$tut" ]; then
    echo "SKIP $tut: not in this checkout"; skipped+=("$tut (not in the checkout)"); continue
  fi
  dirs=()
  if ! out=$(shader_dirs "$tut"); then
    echo "SKIP $tut: its shaders include DiligentFX's; set DILIGENTFX_DIR to a DiligentFX checkout"
    skipped+=("$tut (set DILIGENTFX_DIR)"); continue
  fi
  while IFS= read -r line; do dirs+=("$line"); done <<< "$out"
  split="$OUT/split/$tut"
  python3 "$here/helper.py" split "$notation" "$split" > "$OUT/split/$tut.tsv"
  while IFS=$'\t' read -r idx name; do
    check_pipeline "$tut" "$name" "$split/$idx.json" "$OUT/work" "$OUT/log/$tut/$idx" "${dirs[@]}"
  done < "$OUT/split/$tut.tsv"
done

# Tutorial26_StateCache's own notation, unchanged. Its CMakeLists.txt packs nothing (the tutorial parses
# the file at run time); the command line is Tutorial25's CMake one (-i RenderStates.json -r assets
# -s assets, from the tutorial folder), once for the whole file and once per pipeline (a copy holding
# that pipeline only, so that one pipeline's error does not hide the others').
t26="$checkout/Tutorials/Tutorial26_StateCache"
t26_extra=()
for d in "${extra_dirs[@]}"; do t26_extra+=(-s "$d"); done
echo
echo "Tutorial26_StateCache/assets/RenderStates.json, unchanged, whole file:"
mkdir -p "$OUT/log/t26_whole"
for backend in vulkan opengl; do
  rc=0; run "$OUT/log/t26_whole/$backend.log" "$t26" "$statepack" -i RenderStates.json -r assets -s assets \
    "${t26_extra[@]}" -o "$OUT/log/t26_whole/$backend.spk" "--$backend" --print_contents || rc=$?
  echo "  $backend pack: $(word "$rc") (exit status $rc)"
  [ "$rc" = 0 ] || echo "    first error: $(python3 "$here/helper.py" first-error "$OUT/log/t26_whole/$backend.log")"
  if [ "$backend" = vulkan ] && [ "$rc" = 0 ]; then
    rc=0; run "$OUT/log/t26_whole/verify.log" "$t26" "$statepack" verify "$OUT/log/t26_whole/vulkan.spk" || rc=$?
    echo "  verify:      $(word "$rc") (exit status $rc)"
  fi
done
echo "Tutorial26_StateCache/assets/RenderStates.json, one pipeline at a time:"
python3 "$here/helper.py" split "$t26/assets/RenderStates.json" "$OUT/split/Tutorial26_StateCache" > "$OUT/split/Tutorial26_StateCache.tsv"
while IFS=$'\t' read -r idx name; do
  check_pipeline Tutorial26_StateCache "$name" "$OUT/split/Tutorial26_StateCache/$idx.json" "$t26" \
    "$OUT/log/Tutorial26_StateCache/$idx" -r assets -s assets "${t26_extra[@]}"
done < "$OUT/split/Tutorial26_StateCache.tsv"

echo
echo "== summary"
python3 "$here/helper.py" summary "$results"
if [ ${#skipped[@]} -gt 0 ]; then
  echo
  echo "skipped notation files: ${skipped[*]}"
fi
if [ "$crashed" != 0 ]; then echo; echo "a statepack run crashed or timed out (see the CRASH lines)"; exit 1; fi
exit 0
