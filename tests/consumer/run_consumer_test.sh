#!/usr/bin/env bash
# An external CMake project packs its archive through statepack_add_archive: it builds, a second build
# does nothing, touching an #include'd shader or the JSON repacks, and a broken shader fails the build
# with the shader's file and line while the previous archive survives.
# Usage: run_consumer_test.sh <statepack executable> <StatepackAddArchive.cmake> <work dir>
set -euo pipefail
statepack=$1 module=$2 work=$3
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work"
cp -r "$here" "$work/src"
fail() { echo "FAIL: $*"; exit 1; }
build() { cmake --build "$work/build" 2>&1; }

cmake -S "$work/src" -B "$work/build" -G Ninja -DSTATEPACK_CMAKE="$module" -DSTATEPACK_EXECUTABLE="$statepack" >/dev/null
out=$(build); echo "$out" | grep -q "statepack: packing" || fail "first build did not pack: $out"
archive="$work/build/consumer.spk"
[[ -s "$archive" ]] || fail "no archive"
"$statepack" inspect "$archive" | grep -q "Consumer PSO" || fail "archive lacks the pipeline"

out=$(build); echo "$out" | grep -q "no work to do" || fail "an unchanged project rebuilt: $out"

sleep 1; touch "$work/src/shaders/constants.glsl"
out=$(build); echo "$out" | grep -q "statepack: packing" || fail "touching an #include did not repack: $out"
out=$(build); echo "$out" | grep -q "no work to do" || fail "rebuilt twice after one change: $out"

sleep 1; touch "$work/src/states.json"
out=$(build); echo "$out" | grep -q "statepack: packing" || fail "touching the JSON did not repack: $out"

before=$(cksum < "$archive")
sleep 1; printf '#define ANSWER undefined_name\n' > "$work/src/shaders/constants.glsl"
if out=$(build); then fail "a broken shader built: $out"; fi
echo "$out" | grep -q "constants.glsl:1" || echo "$out" | grep -q "work.comp:6" || fail "no file:line for the error: $out"
[[ "$(cksum < "$archive")" == "$before" ]] || fail "the failed pack changed the previous archive"
echo "consumer project: all checks passed"
