#!/usr/bin/env bash
# STATEPACK_BUILD_PACKAGER=OFF and STATEPACK_BUILD_GL=OFF, as an application that only loads archives
# on Vulkan builds statepack: a fresh
# build of the source tree (shared dearchiver, so that ldd can look at it) in which glslang,
# SPIRV-Tools, spirv-cross and CLI11 are never even looked for (they are installed here,
# so the proof is that the configuration does not know them), no packager, test or sample target exists,
# nothing links a shader compiler, and the installed package has statepack::dearchiver without
# statepack::statepack. (nlohmann_json is the dearchiver's own build dependency: its variants files;
# header-only, so nothing links it.)
# Usage: run_dearchiver_only_test.sh <source root> <work dir>
set -euo pipefail
root=$1 work=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"
build=$work/build

# Debug: the quickest to compile; warnings are still errors.
# STATEPACK_BUILD_GL=OFF too: a Vulkan-only runtime needs neither the shader toolchain nor libepoxy.
cmake -S "$root" -B "$build" -G Ninja -DSTATEPACK_BUILD_PACKAGER=OFF -DSTATEPACK_BUILD_GL=OFF -DSTATEPACK_SHARED=ON \
  -DSTATEPACK_WERROR=ON -DCMAKE_BUILD_TYPE=Debug >"$work/configure.log" 2>&1 ||
  fail "configure failed: $(cat "$work/configure.log")"
# What find_package (<name>_DIR) and pkg_check_modules (__pkg_config_checked_<prefix>) leave in the cache.
# (FindVulkan's own glslangValidator lookup is not the packager's and is left out.)
looked_for='^(glslang|SPIRV-Tools|SPIRV-Tools-opt|CLI11|GTest|glfw3)_DIR:|^__pkg_config_checked_(SPIRV_CROSS_C|IMGUI|EPOXY):'
found=$(grep -E "$looked_for" "$build/CMakeCache.txt" | head -5 || true)
[[ -z "$found" ]] || fail "the packager's dependencies were looked for: $found"
# Tests, samples and benchmarks run the packager, so they are off without it.
for dir in tests samples packager; do
  [[ ! -d "$build/$dir" ]] || fail "$dir/ was configured without the packager"
done

targets=$(ninja -C "$build" -t targets all | cut -d: -f1)
grep -q "libstatepack_dearchiver.so" <<<"$targets" || fail "no dearchiver target: $targets"
bad=$(grep -E '(^|/)(statepack|statepack_packager|statepack_docs|dearchiver_tests|path_tracer|unpack_demo)$|libstatepack_packager|libstatepack_gl' <<<"$targets" || true)
[[ -z "$bad" ]] || fail "targets beyond the dearchiver: $bad"

out=$(cmake --build "$build" 2>&1) || fail "build failed: $out"
commands=$(ninja -C "$build" -t commands)
# Library names and include directories of the toolchain (our own spirv_walk.cpp is not one of them).
found=$(grep -iE 'glslang|SPIRV-Tools|spirv-cross|spirv_cross|libSPIRV' <<<"$commands" | head -3 || true)
[[ -z "$found" ]] || fail "a command uses the shader toolchain: $found"
library=$(find "$build" -name 'libstatepack_dearchiver.so.*' -type f | head -1)
[[ -n "$library" ]] || fail "no shared dearchiver was built"
deps=$(ldd "$library")
grep -q libstdc++ <<<"$deps" || fail "ldd shows no libstdc++, so the checks below prove nothing: $deps"
found=$(grep -iE 'glslang|spirv' <<<"$deps" || true)  # libSPIRV-Tools-shared, libspirv-cross-c-shared
[[ -z "$found" ]] || fail "the dearchiver depends on the shader toolchain: $found"
# The application owns Vulkan dispatch (or the loader is opened at run time): no libvulkan link.
found=$(grep libvulkan <<<"$deps" || true)
[[ -z "$found" ]] || fail "the dearchiver links the Vulkan loader: $found"
# Hidden visibility: the library exports its public API (and the one internal door statepack_gl uses),
# nothing else of statepack's.
# (Standard templates instantiated over public types are the compiler's, not statepack's, and not listed.)
exported=$(nm -DC --defined-only "$library" | grep -E ' [TW] ' | sed 's/^[^ ]* [TW] //' | grep -E '^statepack::[A-Za-z_:]+(\(|$)' || true)
leaked=$(grep -vE '^statepack::(Archive|ArchiveFileWatch|Dearchiver|UnpackedPipeline|UnpackJob|PipelineVariant|detail::ArchiveAccess)::|^statepack::(to_string|load_pipeline_cache|save_pipeline_cache|load_variants|parse_variants)\(' <<<"$exported" || true)
[[ -z "$leaked" ]] || fail "internal symbols exported: $(echo "$leaked" | head -5)"
grep -q '^statepack::Dearchiver::create' <<<"$exported" || fail "Dearchiver::create is not exported: $exported"
echo "exported: $(echo "$exported" | wc -l) symbols, all public API"

cmake --install "$build" --prefix "$work/prefix" >/dev/null || fail "install failed"
[[ ! -e "$work/prefix/bin/statepack" ]] || fail "a packager was installed"
mkdir -p "$work/user"
cat >"$work/user/CMakeLists.txt" <<'EOF2'
cmake_minimum_required(VERSION 3.25)
project(user CXX)  # find_dependency(Vulkan) looks for a library: that needs a language
find_package(statepack CONFIG REQUIRED)
get_target_property(type statepack::dearchiver TYPE)
if(TARGET statepack::statepack OR TARGET statepack::gl OR NOT type STREQUAL "SHARED_LIBRARY")
  message(FATAL_ERROR "expected a shared statepack::dearchiver, no statepack::statepack, no statepack::gl (type ${type})")
endif()
find_package(statepack CONFIG COMPONENTS gl QUIET)  # built without it: the component says so
if(statepack_FOUND)
  message(FATAL_ERROR "find_package(statepack COMPONENTS gl) succeeded on a build without the OpenGL runtime")
endif()
message(STATUS "found the shared dearchiver alone")
EOF2
out=$(cmake -S "$work/user" -B "$work/user/build" -DCMAKE_PREFIX_PATH="$work/prefix" 2>&1) ||
  fail "find_package of the dearchiver-only install: $out"
grep -q "found the shared dearchiver alone" <<<"$out" || fail "$out"

echo "$(basename "$library"): $(echo "$deps" | wc -l) shared libraries, none a shader compiler"
echo "dearchiver only: all checks passed"
