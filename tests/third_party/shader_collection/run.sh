#!/usr/bin/env bash
# Packs every pipeline of the SaschaWillems/Vulkan shader collection with statepack, for Vulkan, for
# OpenGL and for both, links every OpenGL archive with gl_demo, and prints a summary (see README.md).
# Not part of the CI suite: it needs a checkout of https://github.com/SaschaWillems/Vulkan, and CI has
# no network.
#
# usage: tests/third_party/shader_collection/run.sh /path/to/SaschaWillems-Vulkan-checkout [WORK]
#   The checkout is a plain folder (no git needed) with shaders/{glsl,hlsl}/ and, optionally, examples/.
#   WORK: output folder (default: a fresh temporary folder); its src, notation, log and out subfolders
#   are replaced. Environment: STATEPACK, GL_DEMO (default build/bin/{statepack,gl_demo} of this repository).
# Exit status: 0, or 1 if any statepack or gl_demo run crashed or timed out (exit >= 124), 2 on usage error.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 /path/to/SaschaWillems-Vulkan-checkout [WORK]" >&2; exit 2
fi
checkout=$(cd "$1" && pwd)
if [ ! -d "$checkout/shaders/glsl" ] || [ ! -d "$checkout/shaders/hlsl" ]; then
  echo "error: $checkout has no shaders/glsl and shaders/hlsl: not a SaschaWillems/Vulkan checkout?" >&2; exit 2
fi
WORK=${2:-$(mktemp -d)}
mkdir -p "$WORK"; WORK=$(cd "$WORK" && pwd)
STATEPACK=${STATEPACK:-$root/build/bin/statepack}
GL_DEMO=${GL_DEMO:-$root/build/bin/gl_demo}
for b in "$STATEPACK" "$GL_DEMO"; do
  [ -x "$b" ] || { echo "error: $b not found or not executable (build the project, or set STATEPACK/GL_DEMO)" >&2; exit 2; }
done
export WORK STATEPACK GL_DEMO
echo "checkout: $checkout"
echo "WORK:     $WORK"

# 1. Export the shader sources (no precompiled .spv, no slang) and write one notation file per pipeline.
rm -rf "$WORK/src" "$WORK/notation" "$WORK/log" "$WORK/out"
mkdir -p "$WORK/src/shaders" "$WORK/log" "$WORK/out"
tar -C "$checkout/shaders" --exclude='*.spv' -cf - glsl hlsl | tar -C "$WORK/src/shaders" -xf -
SHADERS="$WORK/src/shaders" EXAMPLES="$checkout/examples" python3 "$here/make_notation.py"

# 2. Pack each pipeline with --vulkan, --opengl, and both (2 at a time, 60 s each, one thread each).
pack_one() {  # NAME MODE(vk|gl|both) -> WORK/log/NAME.MODE.{log,rc}, WORK/out/NAME_MODE.spk
  local name=$1 mode=$2 dir flags rc=0
  dir=$(awk -F'\t' -v n="$name" '$1==n{print $4}' "$WORK/pipelines.tsv")
  case $mode in vk) flags=--vulkan;; gl) flags=--opengl;; both) flags="--vulkan --opengl";; esac
  (cd "$WORK/notation" && timeout 60 "$STATEPACK" pack -t 1 -i "$name.json" -s "$dir" \
     -o "$WORK/out/${name}_${mode}.spk" $flags) > "$WORK/log/$name.$mode.log" 2>&1 || rc=$?
  echo "$rc" > "$WORK/log/$name.$mode.rc"
}
# 3. Link each OpenGL archive that packed -> WORK/log/NAME.gldemo.{log,rc}
gldemo_one() {
  local name=$1 rc=0
  timeout 60 "$GL_DEMO" "$WORK/out/${name}_gl.spk" > "$WORK/log/$name.gldemo.log" 2>&1 || rc=$?
  echo "$rc" > "$WORK/log/$name.gldemo.rc"
}
export -f pack_one gldemo_one
n=$(wc -l < "$WORK/pipelines.tsv")
echo "packing $n pipelines x 3 (vk, gl, both) ..."
cut -f1 "$WORK/pipelines.tsv" | awk '{print $1" vk"; print $1" gl"; print $1" both"}' \
  | xargs -P 2 -n 2 bash -c 'pack_one "$@"' _
echo "linking the OpenGL archives with gl_demo ..."
cut -f1 "$WORK/pipelines.tsv" | while read -r name; do
  if [ "$(cat "$WORK/log/$name.gl.rc")" = 0 ]; then echo "$name"; fi
done | xargs -r -P 2 -n 1 bash -c 'gldemo_one "$@"' _

# 4. Summary, then the OpenGL failures by cause.
echo
status=0
python3 "$here/summarize.py" "$WORK" || status=$?
echo
python3 "$here/classify.py" "$WORK" gl
echo
echo "logs: $WORK/log, archives: $WORK/out, notation: $WORK/notation"
exit $((status != 0))
