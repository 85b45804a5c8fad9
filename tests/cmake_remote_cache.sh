#!/usr/bin/env bash
# statepack_add_archive behind a team's server: the REMOTE_CACHE keyword, and the cache variable
# STATEPACK_REMOTE_CACHE for every archive without it, each pack's compiles written to its server (a
# shared directory here), NO_CACHE none (not even $STATEPACK_REMOTE_CACHE's); the archives are the bytes of a
# pack without any cache.
# Usage: cmake_remote_cache.sh <statepack> <StatepackAddArchive.cmake> <work dir>
set -euo pipefail
statepack=$1 module=$2 work=$3
rm -rf "$work"
mkdir -p "$work/src"
cat > "$work/src/project.json" << 'JSON'
{"Pipelines": [{"PSODesc": {"Name": "Fill"}, "pCS": {"Desc": {"Name": "Fill CS"}, "FilePath": "fill.comp"}}]}
JSON
cat > "$work/src/fill.comp" << 'GLSL'
#version 450
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) buffer Data { uint v[]; } data;
void main() { data.v[gl_GlobalInvocationID.x] = gl_GlobalInvocationID.x; }
GLSL
cat > "$work/src/CMakeLists.txt" << CMAKE
cmake_minimum_required(VERSION 3.25)
project(remote_cache_consumer NONE)
include("$module")
# (A local cache each: sharing one, the second pack would find everything there and send nothing.)
statepack_add_archive(keyword OUTPUT keyword.spk INPUTS project.json PACKAGER "$statepack"
                      CACHE_DIR keyword-cache REMOTE_CACHE "file:$work/keyword-server")
statepack_add_archive(variable OUTPUT variable.spk INPUTS project.json PACKAGER "$statepack"
                      CACHE_DIR variable-cache)
statepack_add_archive(none OUTPUT none.spk INPUTS project.json PACKAGER "$statepack" NO_CACHE)
CMAKE
cmake -S "$work/src" -B "$work/build" -G Ninja "-DSTATEPACK_REMOTE_CACHE=file:$work/variable-server" > /dev/null
# (NO_CACHE: no server either, though the environment names one.)
STATEPACK_REMOTE_CACHE="file:$work/environment-server" cmake --build "$work/build" > /dev/null
[[ ! -e "$work/environment-server" ]] || { echo "FAIL: a NO_CACHE archive wrote to \$STATEPACK_REMOTE_CACHE"; exit 1; }
(cd "$work/src" && "$statepack" pack -i project.json -o "$work/clean.spk" --vulkan)
cmp "$work/clean.spk" "$work/build/none.spk" || { echo "FAIL: none.spk differs from a pack without a cache"; exit 1; }
for name in keyword variable; do
  cmp "$work/clean.spk" "$work/build/$name.spk" || { echo "FAIL: $name.spk differs from a pack without a cache"; exit 1; }
  entries=$(find "$work/$name-server" -type f ! -name '.tmp*' | wc -l)
  [[ $entries == 2 ]] || { echo "FAIL: $name-server holds $entries entries, not 2 (the compile and its finalisation)"; exit 1; }
done
echo "remote cache through statepack_add_archive: both servers written, archives byte-identical"
