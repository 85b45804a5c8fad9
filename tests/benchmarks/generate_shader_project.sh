#!/usr/bin/env bash
# Writes DIR/project.json with N compute pipelines, each with a shader file of its own, so all N compile
# to different modules and a change to one file changes one shader, as in a project of N real shaders:
# - real (the default): the path tracer's compute shader (about 480 lines with its #includes, shared by
#   all) with one line of its own (an early return for a work-group z no dispatch reaches);
# - small: a compute shader of about ten lines that writes its own constant into a storage buffer.
# Usage: generate_shader_project.sh <repository root> <dir> <N> [real|small]
set -euo pipefail
root=$1 dir=$2 count=$3 kind=${4:-real}
[[ $kind == real || $kind == small ]] || { echo "generate_shader_project.sh: kind is real or small, not '$kind'" >&2; exit 2; }
mkdir -p "$dir"
source_file="$root/shaders/path_tracer/path_trace.comp"
[[ $kind == real ]] && cp "$root"/shaders/path_tracer/*.glsl "$dir/"
{
  echo '{ "Pipelines": ['
  for ((i = 0; i < count; ++i)); do
    if [[ $kind == real ]]; then
      sed "s|^void main() {|void main() {\n  if (gl_GlobalInvocationID.z == $((i + 1000000))u) return;  // copy $i|" \
        "$source_file" > "$dir/shader_$i.comp"
    else
      cat > "$dir/shader_$i.comp" << SHADER
#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) buffer Values { uint values[]; };
layout(push_constant) uniform Push { uint count; } push;

void main() {
  if (gl_GlobalInvocationID.z == $((i + 1000000))u) return;  // copy $i
  uint index = gl_GlobalInvocationID.x;
  if (index < push.count) values[index] = index * $((i + 3))u + 1u;
}
SHADER
    fi
    [[ $i -gt 0 ]] && echo ','
    printf '{ "PSODesc": { "Name": "Compute %d" }, "pCS": { "Desc": { "Name": "CS %d" }, "FilePath": "shader_%d.comp" } }' \
      "$i" "$i" "$i"
  done
  echo '] }'
} > "$dir/project.json"
