#!/usr/bin/env bash
# The samples as a user builds them: statepack installed into a prefix, then samples/ configured as a
# project of its own against that prefix (find_package(statepack)), built with -Werror, and each sample
# run on lavapipe with validation on. Proves the samples need nothing but what the package installs:
# no include path into the source tree's libraries, no target of statepack's own build.
# Usage: run_samples_install_test.sh <statepack build dir> <its configuration> <source dir> <work dir>
set -euo pipefail
build_dir=$1 config=$2 src=$3 work=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"

cmake --install "$build_dir" --config "$config" --prefix "$work/prefix" >"$work/install.log" ||
  fail "cmake --install failed: $(cat "$work/install.log")"
for h in vulkan_context.hpp gl_context.hpp host_tools.hpp; do
  [[ -f "$work/prefix/include/statepack/bootstrap/$h" ]] || fail "not installed: include/statepack/bootstrap/$h"
done
export PATH=/usr/bin:/bin  # the installed packager packs, not one on PATH
# -fno-lto: the samples link the runtime's machine code here (seconds less a link; see run_install_test.sh).
cmake -S "$src/samples" -B "$work/samples" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_CXX_FLAGS=-Werror -DCMAKE_EXE_LINKER_FLAGS=-fno-lto >"$work/configure.log" 2>&1 || fail "configure failed: $(cat "$work/configure.log")"
cmake --build "$work/samples" --parallel 2 >"$work/build.log" 2>&1 || fail "build failed: $(tail -c 4000 "$work/build.log")"
grep -q "statepack: packing" "$work/build.log" || fail "no archive was packed: $(tail -c 2000 "$work/build.log")"
grep -qF "$work/prefix/bin/statepack" "$work/samples/build.ninja" || fail "the archives were not packed by the installed statepack"
# Nothing of statepack's own tree but samples/ itself, and nothing of its build.
# (The work folder may lie inside the build folder: its own paths are not the build's.)
internal=$(grep -oE -- "-(I|isystem) ?[^ ]+" "$work/samples/build.ninja" | grep -vF "$work" |
  grep -F -e "$src/dearchiver" -e "$src/packager" -e "$build_dir" || true)
[[ -z "$internal" ]] || fail "a sample reaches into statepack's tree: $internal"
grep -q -- "-I$work/prefix/include\|-isystem $work/prefix/include" "$work/samples/build.ninja" || fail "the samples do not use the installed headers"

out=$("$work/samples/unpack_demo" 2>&1) || fail "unpack_demo failed: $out"
grep -q "validation layer on" <<<"$out" || fail "unpack_demo: $out"
grep -q "ran '" <<<"$out" || fail "unpack_demo ran no pipeline: $out"
echo "unpack_demo: $(grep -c "ran '" <<<"$out") pipeline(s) run"
if [[ -x "$work/samples/gl_demo" ]]; then
  out=$("$work/samples/gl_demo" 2>&1) || fail "gl_demo failed: $out"
  echo "gl_demo: $(echo "$out" | tail -n 1)"
fi
out=$("$work/samples/path_tracer" --headless --width 64 --height 48 --spp 4 --out "$work/pt.png" 2>&1) ||
  fail "path_tracer failed: $out"
[[ -s "$work/pt.png" ]] || fail "path_tracer wrote no image: $out"
echo "path_tracer: $(echo "$out" | tail -n 1)"
echo "samples against the installed package: all checks passed"
