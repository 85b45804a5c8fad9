#!/usr/bin/env bash
# Runs statepack on Diligent Engine's Tutorial25_StatePackager exactly as the tutorial's CMakeLists.txt
# runs Diligent's packager (same working directory, same command line), then unpacks the archive with
# `statepack verify` (Vulkan) and gl_demo (OpenGL), and prints PASS/FAIL lines.
# Not part of the CI suite: it needs a checkout of https://github.com/DiligentGraphics/DiligentSamples,
# and CI has no network. Nothing is written into the checkout: the archive goes to a temporary folder.
#
# usage: tests/third_party/diligent_tutorial25.sh /path/to/DiligentSamples-checkout [build-dir]
#   build-dir: this repository's build folder, holding bin/statepack and bin/gl_demo (default: build)
# Exit status: 0 if every check passed, 1 if one failed, 2 on usage error.
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 /path/to/DiligentSamples-checkout [build-dir]" >&2; exit 2
fi
tutorial="$1/Tutorials/Tutorial25_StatePackager"
build=${2:-$root/build}
statepack="$build/bin/statepack"
gl_demo="$build/bin/gl_demo"
[ -f "$tutorial/assets/RenderStates.json" ] || { echo "error: $tutorial/assets/RenderStates.json not found: not a DiligentSamples checkout?" >&2; exit 2; }
for b in "$statepack" "$gl_demo"; do
  [ -x "$b" ] || { echo "error: $b not found or not executable (build the project, or give the build folder)" >&2; exit 2; }
done
statepack=$(cd "$(dirname "$statepack")" && pwd)/statepack
gl_demo=$(cd "$(dirname "$gl_demo")" && pwd)/gl_demo

OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
failed=0
check() {  # NAME CONDITION-STATUS
  if [ "$2" = 0 ]; then echo "PASS: $1"; else echo "FAIL: $1"; failed=1; fi
}
run() {  # LOG COMMAND... : runs it (stdout to LOG, stderr to LOG.err), shows both, returns its exit status
  local log=$1 rc=0; shift
  echo "\$ $*"
  "$@" > "$log" 2> "$log.err" || rc=$?
  cat "$log" "$log.err"
  return "$rc"
}

cd "$tutorial"
rc=0; run "$OUT/pack.log" "$statepack" -i RenderStates.json -r assets -s assets -o "$OUT/StateArchive.bin" \
  --dx11 --dx12 --webgpu --opengl --vulkan --metal_macos --metal_ios --print_contents || rc=$?
check "statepack pack (Diligent's command line) exits 0 (got $rc)" "$rc"
for pso in 'G-Buffer PSO' 'Path Trace PSO' 'Resolve PSO'; do
  for kind in '' 'OpenGL '; do
    st=0; grep -q "^${kind}pipeline '$pso'" "$OUT/pack.log" || st=1
    check "pack output lists ${kind}pipeline '$pso'" "$st"
  done
done
if [ -f "$OUT/StateArchive.bin" ]; then
  rc=0; run "$OUT/verify.log" "$statepack" verify "$OUT/StateArchive.bin" || rc=$?
  check "statepack verify exits 0 (got $rc)" "$rc"
  rc=0; run "$OUT/gl_demo.log" "$gl_demo" "$OUT/StateArchive.bin" || rc=$?
  check "gl_demo exits 0 (got $rc)" "$rc"
  st=0; grep -qxF "0 GL error message(s)" "$OUT/gl_demo.log" || st=1
  check "gl_demo printed '0 GL error message(s)'" "$st"
else
  check "statepack wrote $OUT/StateArchive.bin" 1
fi
if [ "$failed" = 0 ]; then echo "PASS: Tutorial25_StatePackager"; else echo "FAIL: Tutorial25_StatePackager"; fi
exit "$failed"
