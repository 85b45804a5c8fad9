#version 450
// White: with blend factor CONSTANT_COLOR and ZERO, the target receives the blend constants. The
// vertex shader's uv is read (and multiplied away) so that the interface matches.
layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;
void main() { out_color = vec4(1.0) + vec4(0.0 * in_uv.x); }
