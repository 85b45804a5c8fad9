#!/usr/bin/env bash
# An external CMake project packs its archive through statepack_add_archive: it builds, a second build
# does nothing, touching an #include'd shader or the JSON repacks, and a broken shader fails the build
# with the shader's file and line while the previous archive survives; its <target>_watch target repacks
# on an edit and ends on SIGINT. Unix Makefiles build it into a new
# directory, Ninja Multi-Config packs it once for two configurations, and a misspelt keyword of the
# function is named. Last, the C++ a user copies from README.md and docs/ compiles against the public
# headers without warnings (compile_doc_snippets.sh).
# Usage: run_consumer_test.sh <statepack executable> <StatepackAddArchive.cmake> <work dir> <source root>
#        <C++ compiler>
set -euo pipefail
statepack=$1 module=$2 work=$3 source_root=$4 cxx=$5
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work"
cp -r "$here" "$work/src"
fail() { echo "FAIL: $*"; exit 1; }
build() { cmake --build "$work/build" 2>&1; }

cmake -S "$work/src" -B "$work/build" -G Ninja -DSTATEPACK_CMAKE="$module" -DSTATEPACK_EXECUTABLE="$statepack" >/dev/null
out=$(build); grep -q "statepack: packing" <<<"$out" || fail "first build did not pack: $out"
archive="$work/build/consumer.spk"
[[ -s "$archive" ]] || fail "no archive"
"$statepack" inspect "$archive" | grep -q "Consumer PSO" || fail "archive lacks the pipeline"

out=$(build); grep -q "no work to do" <<<"$out" || fail "an unchanged project rebuilt: $out"

sleep 1; touch "$work/src/shaders/constants.glsl"
out=$(build); grep -q "statepack: packing" <<<"$out" || fail "touching an #include did not repack: $out"
out=$(build); grep -q "no work to do" <<<"$out" || fail "rebuilt twice after one change: $out"

sleep 1; touch "$work/src/states.json"
out=$(build); grep -q "statepack: packing" <<<"$out" || fail "touching the JSON did not repack: $out"

before=$(cksum < "$archive")
sleep 1; printf '#define ANSWER undefined_name\n' > "$work/src/shaders/constants.glsl"
if out=$(build); then fail "a broken shader built: $out"; fi
grep -q "constants.glsl:1" <<<"$out" || grep -q "work.comp:6" <<<"$out" || fail "no file:line for the error: $out"
[[ "$(cksum < "$archive")" == "$before" ]] || fail "the failed pack changed the previous archive"

# <target>_watch: not built by `all` (the builds above returned), it packs, repacks after an edit of an
# #include with the new SPIR-V, and ends on SIGINT. It runs in a session of its own, so that the signal
# reaches cmake, ninja and the packager, as Ctrl-C does.
cp "$here/shaders/constants.glsl" "$work/src/shaders/constants.glsl"
setsid cmake --build "$work/build" --target consumer_archive_watch >"$work/watch.log" 2>&1 &
watch_pid=$!
wait_for() {
  for _ in $(seq 100); do grep -q "$1" "$work/watch.log" && return 0; sleep 0.1; done
  kill -KILL -- -"$watch_pid" || true
  fail "consumer_archive_watch: no '$1': $(cat "$work/watch.log")"
}
wait_for "^packed .*consumer.spk"
first=$(cksum < "$archive")
printf '#define ANSWER 43u\n' > "$work/src/shaders/constants.glsl"
wait_for "^repacked .*consumer.spk.*(changed: .*constants.glsl)"
[[ "$(cksum < "$archive")" != "$first" ]] || fail "consumer_archive_watch: the repack left the archive as it was"
kill -INT -- -"$watch_pid"
wait "$watch_pid" || true
grep -q "^stopped by SIGINT" "$work/watch.log" || fail "consumer_archive_watch did not stop on SIGINT: $(cat "$work/watch.log")"
[[ -z "$(find "$work/build" -maxdepth 1 -name '.*statepack-tmp*')" ]] || fail "consumer_archive_watch left a temporary"
# Unix Makefiles too: the function creates the output's directory itself (Ninja does, Make does not).
cp -r "$here" "$work/make-src"
sed -i 's|OUTPUT consumer.spk|OUTPUT nested/dir/consumer.spk|' "$work/make-src/CMakeLists.txt"
cmake -S "$work/make-src" -B "$work/make/build" -G "Unix Makefiles" -DSTATEPACK_CMAKE="$module" \
  -DSTATEPACK_EXECUTABLE="$statepack" >/dev/null || fail "Unix Makefiles configure failed"
out=$(cmake --build "$work/make/build" 2>&1) || fail "Unix Makefiles build failed: $out"
[[ -s "$work/make/build/nested/dir/consumer.spk" ]] || fail "Unix Makefiles: no archive in a new directory: $out"

# Ninja Multi-Config: one build directory for several configurations. The archive does not depend on
# the configuration, so it is packed once, and building a second configuration leaves it alone.
cp -r "$here" "$work/multi-src"
cmake -S "$work/multi-src" -B "$work/multi/build" -G "Ninja Multi-Config" -DSTATEPACK_CMAKE="$module" \
  -DSTATEPACK_EXECUTABLE="$statepack" >/dev/null || fail "Ninja Multi-Config configure failed"
out=$(cmake --build "$work/multi/build" --config Debug 2>&1) || fail "Ninja Multi-Config build failed: $out"
[[ -s "$work/multi/build/consumer.spk" ]] || fail "Ninja Multi-Config: no archive: $out"
out=$(cmake --build "$work/multi/build" --config Release 2>&1) || fail "Ninja Multi-Config Release build failed: $out"
grep -q "statepack: packing" <<<"$out" && fail "Ninja Multi-Config: a second configuration repacked: $out"

# A misspelt keyword is named, not reported as a missing OUTPUT.
mkdir -p "$work/typo"
cat > "$work/typo/CMakeLists.txt" <<EOF2
cmake_minimum_required(VERSION 3.25)
project(typo NONE)
include("$module")
statepack_add_archive(typo OUPTUT x.spk INPUTS states.json PACKAGER "$statepack")
EOF2
out=$(cmake -S "$work/typo" -B "$work/typo/build" 2>&1) && fail "a misspelt keyword configured: $out"
grep -q "unknown arguments OUPTUT;x.spk" <<<"$out" || fail "the misspelt keyword is not named: $out"

# The documentation's C++ compiles as an application would compile it.
out=$(bash "$here/compile_doc_snippets.sh" "$source_root" "$cxx" "$work/doc_snippets" 2>&1) ||
  fail "documentation snippets: $out"
echo "$out"

echo "consumer project: all checks passed"
