#!/usr/bin/env bash
# `cmake --install` as a user runs it: install into a staging prefix, move the prefix elsewhere (every
# installed path must be relative to it), then build the consumer project against it through
# find_package(statepack) with Ninja and Ninja Multi-Config (a Debug build picking up the installed
# RelWithDebInfo packager), check that its archive was packed by the installed statepack, and run the
# application it links against statepack::dearchiver. Last, the same application built with only the
# pkg-config file's flags.
# Usage: run_install_test.sh <statepack build dir> <its configuration> <work dir> <C++ compiler>
set -euo pipefail
build_dir=$1 config=$2 work=$3 cxx=$4
here=$(cd "$(dirname "$0")" && pwd)
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"

cmake --install "$build_dir" --config "$config" --prefix "$work/staged" >"$work/install.log" ||
  fail "cmake --install failed: $(cat "$work/install.log")"
mv "$work/staged" "$work/prefix"
prefix=$work/prefix
config_file=$(find "$prefix" -name statepackConfig.cmake)
[[ -n "$config_file" ]] || fail "no statepackConfig.cmake under the prefix"
config_dir=$(dirname "$config_file") libdir=$(dirname "$(dirname "$config_dir")")
for f in "$prefix/bin/statepack" "$libdir/libstatepack_dearchiver.a" "$libdir/libstatepack_gl.a" "$config_dir/statepackConfigVersion.cmake" \
  "$config_dir/statepackTargets.cmake" "$config_dir/StatepackAddArchive.cmake" "$libdir/pkgconfig/statepack_dearchiver.pc" \
  "$prefix/include/statepack/dearchiver.hpp" "$prefix/include/statepack/result.hpp"; do
  [[ -f "$f" ]] || fail "not installed: ${f#"$prefix/"}"
done
# Only the public headers (the libraries' and the bootstrap's): the internal ones stay private.
headers=$(cd "$prefix/include" && find . -type f | sort | tr '\n' ' ')
[[ "$headers" == "./statepack/bootstrap/gl_context.hpp ./statepack/bootstrap/host_tools.hpp ./statepack/bootstrap/vulkan_context.hpp ./statepack/dearchiver.hpp ./statepack/export.hpp ./statepack/gl_dearchiver.hpp ./statepack/result.hpp " ]] ||
  fail "installed headers: $headers"
grep -rq "$build_dir" "$config_dir" "$libdir/pkgconfig" && fail "an installed CMake or pkg-config file names the build tree"

# The packager on PATH must not be what the build uses: the installed function runs statepack::statepack.
export PATH=/usr/bin:/bin
command -v statepack >/dev/null && fail "a statepack on PATH would hide what the function runs"
# shellcheck source=validation.sh
source "$here/validation.sh"  # validated, no_validation_messages
consume() {  # <generator> <configuration> <where the application lands>
  local dir="$work/$1" config=$2
  cp -r "$here" "$dir-src"
  # -fno-lto: these programs link the runtime's machine code, not its LTO code (a consumer may turn it
  # off; cmake.consumer_project and the documented projects link with it), which saves seconds a link.
  cmake -S "$dir-src" -B "$dir" -G "$1" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_EXE_LINKER_FLAGS=-fno-lto >"$dir.log" 2>&1 ||
    fail "$1: configure against the installed prefix failed: $(cat "$dir.log")"
  out=$(cmake --build "$dir" --config "$config" 2>&1) || fail "$1: build failed: $out"
  grep -q "statepack: packing" <<<"$out" || fail "$1: the archive was not packed: $out"
  grep -rqF --include="*.ninja" "$prefix/bin/statepack" "$dir" || fail "$1: the pack command is not the installed statepack"
  out=$(validated "$dir/$3/consumer_app" "$dir/consumer.spk") || fail "$1: consumer_app failed: $out"
  grep -q "unpacked 'Consumer PSO'" <<<"$out" || fail "$1: consumer_app: $out"
  no_validation_messages "$1: consumer_app" "$out"
  echo "$1 ($config): $out"
  # Owning dispatch through volk: the application needs no libvulkan, directly or through statepack.
  needs=$(readelf -d "$dir/$3/consumer_volk_app" | grep NEEDED)
  grep -q libc.so <<<"$needs" || fail "$1: readelf shows no NEEDED entries, so the check proves nothing: $needs"
  grep -q libvulkan <<<"$needs" && fail "$1: consumer_volk_app links the Vulkan loader: $needs"
  out=$(validated "$dir/$3/consumer_volk_app" "$dir/consumer.spk") || fail "$1: consumer_volk_app failed: $out"
  grep -q "unpacked 'Consumer PSO' (.*) through volk" <<<"$out" || fail "$1: consumer_volk_app: $out"
  no_validation_messages "$1: consumer_volk_app" "$out"
  echo "$1 ($config): $out"
  out=$("$dir/$3/consumer_gl_app" "$dir/consumer_gl.spk" 2>&1) || fail "$1: consumer_gl_app failed: $out"
  grep -q "unpacked 'Consumer PSO' on OpenGL" <<<"$out" || fail "$1: consumer_gl_app: $out"
  echo "$1 ($config): $out"
}
consume Ninja "" .
consume "Ninja Multi-Config" Debug Debug

# pkg-config alone: the flags it gives compile and link the same application.
# The application calls Vulkan itself, so it asks for the loader too (the library does not link one).
flags=$(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --cflags --libs statepack_dearchiver vulkan) ||
  fail "pkg-config does not know statepack_dearchiver"
includedir=$(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --variable=includedir statepack_dearchiver)
[[ -f "$includedir/statepack/dearchiver.hpp" ]] || fail "pkg-config: the include directory lacks the headers: $flags"
# shellcheck disable=SC2086 # the flags are words
"$cxx" -std=c++20 "$here/app.cpp" -o "$work/pkg-config-app" $flags || fail "pkg-config build failed (flags: $flags)"
out=$("$work/pkg-config-app" "$work/Ninja/consumer.spk" 2>&1) || fail "pkg-config build's application failed: $out"
echo "pkg-config: $out"
# The same for the OpenGL runtime: statepack_gl's flags (which bring the dearchiver's and libepoxy's).
gl_flags=$(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --cflags --libs statepack_gl) ||
  fail "pkg-config does not know statepack_gl"
# shellcheck disable=SC2086 # the flags are words
"$cxx" -std=c++20 "$here/gl_app.cpp" -o "$work/pkg-config-gl-app" $gl_flags ||
  fail "pkg-config build of the GL application failed (flags: $gl_flags)"
out=$("$work/pkg-config-gl-app" "$work/Ninja/consumer_gl.spk" 2>&1) || fail "pkg-config GL application failed: $out"
grep -q "unpacked 'Consumer PSO' on OpenGL" <<<"$out" || fail "pkg-config GL application: $out"
echo "pkg-config (OpenGL): $out"

# Adoption edges: a project without C++ (LANGUAGES NONE) still packs with the installed package; an
# input found through RENDER_STATE_DIRS (Diligent's -r) packs; a wrong INPUTS path is this function's
# error at configure time, not the generator's "no rule to make target" at build time.
mkdir -p "$work/none-src/assets" "$work/none-src/shaders"
cp "$here/states.json" "$work/none-src/assets/"
cp -r "$here/shaders/." "$work/none-src/shaders/"
cat >"$work/none-src/CMakeLists.txt" <<'EOF2'
cmake_minimum_required(VERSION 3.25)
project(packs_only LANGUAGES NONE)
find_package(statepack CONFIG REQUIRED)
statepack_add_archive(states OUTPUT states.spk INPUTS states.json RENDER_STATE_DIRS assets SHADER_DIRS shaders)
EOF2
cmake -S "$work/none-src" -B "$work/none" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >"$work/none.log" 2>&1 ||
  fail "LANGUAGES NONE: configure failed: $(cat "$work/none.log")"
grep -q "Could NOT find Vulkan" "$work/none.log" && fail "LANGUAGES NONE: $(cat "$work/none.log")"
cmake --build "$work/none" >>"$work/none.log" 2>&1 || fail "LANGUAGES NONE: build failed: $(cat "$work/none.log")"
[[ -s "$work/none/states.spk" ]] || fail "LANGUAGES NONE: no archive"
sed -i 's/INPUTS states.json/INPUTS stats.json/' "$work/none-src/CMakeLists.txt"
if cmake -S "$work/none-src" -B "$work/none-typo" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >"$work/typo.log" 2>&1; then
  fail "a wrong INPUTS path configured"
fi
grep -q "statepack_add_archive(states): INPUTS file 'stats.json' not found" "$work/typo.log" ||
  fail "a wrong INPUTS path: $(cat "$work/typo.log")"
echo "adoption edges: LANGUAGES NONE packs, RENDER_STATE_DIRS inputs found, a wrong INPUTS path is a configure error"

echo "installed package: all checks passed"
