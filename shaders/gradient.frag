#version 450
#extension GL_GOOGLE_include_directive : require
#include "color_ramp.glsl"

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

void main() { out_color = color_ramp(in_uv); }
