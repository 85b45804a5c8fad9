#!/usr/bin/env bash
# statepack inside another project through add_subdirectory: configured (not built), it offers the
# packager, statepack::dearchiver and statepack_add_archive, but none of its tests, samples or benchmarks,
# which only a top-level build of statepack gets by default.
# Usage: run_subproject_test.sh <source root> <work dir>
set -euo pipefail
root=$1 work=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work/app"
cp "$(dirname "$0")/states.json" "$work/app/"
cp -r "$(dirname "$0")/shaders" "$work/app/"
cat >"$work/app/CMakeLists.txt" <<EOF2
cmake_minimum_required(VERSION 3.25)
project(app CXX)
add_subdirectory("$root" statepack)
statepack_add_archive(app_archive OUTPUT app.spk INPUTS states.json SHADER_DIRS shaders)
add_library(app STATIC IMPORTED)  # only the link to the dearchiver matters here
target_link_libraries(app INTERFACE statepack::dearchiver)
EOF2
out=$(cmake -S "$work/app" -B "$work/build" -G Ninja 2>&1) || fail "configure failed: $out"
targets=$(ninja -C "$work/build" -t targets all | cut -d: -f1)
for wanted in statepack statepack_dearchiver app_archive; do
  grep -qx "$wanted" <<<"$targets" || fail "no $wanted target"
done
bad=$(grep -xE 'dearchiver_tests|packager_cli_tests|path_tracer|unpack_demo|load_benchmark|archive_fuzzer' <<<"$targets" || true)
[[ -z "$bad" ]] || fail "a subproject build has statepack's own tests, samples or benchmarks: $bad"
[[ ! -e "$work/build/CTestTestfile.cmake" ]] || fail "statepack registered tests in the parent project"
# The parent's build type stands, also none: statepack does not force its RelWithDebInfo on it.
build_type=$(grep -E '^CMAKE_BUILD_TYPE:' "$work/build/CMakeCache.txt" | cut -d= -f2- || true)
[[ -z "$build_type" ]] || fail "the parent project's empty build type became '$build_type'"
echo "subproject: all checks passed"
