#!/usr/bin/env bash
# Writes DIR/project.json with N compute pipelines, each with a shader file of its own: the path tracer's
# compute shader (about 480 lines with its #includes, shared by all) with one line of its own (an early
# return for a work-group z no dispatch reaches), so all N compile to different modules and a change to
# one file changes one shader, as in a project of N real shaders.
# Usage: generate_shader_project.sh <repository root> <dir> <N>
set -euo pipefail
root=$1 dir=$2 count=$3
mkdir -p "$dir"
cp "$root"/shaders/path_tracer/*.glsl "$dir/"
source_file="$root/shaders/path_tracer/path_trace.comp"
{
  echo '{ "Pipelines": ['
  for ((i = 0; i < count; ++i)); do
    sed "s|^void main() {|void main() {\n  if (gl_GlobalInvocationID.z == $((i + 1000000))u) return;  // copy $i|" \
      "$source_file" > "$dir/shader_$i.comp"
    [[ $i -gt 0 ]] && echo ','
    printf '{ "PSODesc": { "Name": "Compute %d" }, "pCS": { "Desc": { "Name": "CS %d" }, "FilePath": "shader_%d.comp" } }' \
      "$i" "$i" "$i"
  done
  echo '] }'
} > "$dir/project.json"
