#!/usr/bin/env bash
# Writes DIR/generated.json with N pipelines (N/2 graphics sharing a vertex shader with their own pixel
# shader, N/2 compute), each shader with its own macro so all N+1 are compiled, plus the sample shaders.
# Usage: generate_pipelines.sh <repository root> <dir> <N>
set -euo pipefail
root=$1 dir=$2 count=$3
mkdir -p "$dir"
cp "$root/shaders/fullscreen_triangle.vert" "$root/shaders/gradient.frag" "$root/shaders/color_ramp.glsl" \
   "$root/shaders/fill_buffer.comp" "$dir/"
{
  echo '{ "Defaults": { "Pipeline": { "GraphicsPipeline": { "RTVFormats": { "0": "RGBA8_UNORM" },'
  echo '  "DepthStencilDesc": { "DepthEnable": false }, "RasterizerDesc": { "CullMode": "NONE" } } } },'
  echo '  "Pipelines": ['
  for ((i = 0; i < count; i++)); do
    [[ $i -gt 0 ]] && echo ','
    if ((i % 2 == 0)); then
      printf '{ "PSODesc": { "Name": "Graphics %d" }, "pVS": { "Desc": { "Name": "VS" }, "FilePath": "fullscreen_triangle.vert" },' "$i"
      printf ' "pPS": { "Desc": { "Name": "PS %d" }, "FilePath": "gradient.frag", "Macros": [{ "Name": "VARIANT", "Definition": "%d" }] } }' "$i" "$i"
    else
      printf '{ "PSODesc": { "Name": "Compute %d" }, "pCS": { "Desc": { "Name": "CS %d" }, "FilePath": "fill_buffer.comp",' "$i" "$i"
      printf ' "Macros": [{ "Name": "VARIANT", "Definition": "%d" }] } }' "$i"
    fi
  done
  echo '] }'
} > "$dir/generated.json"
