#version 450
layout(location = 0) in vec2 uv;
layout(location = 0) out vec4 color;
layout(location = 1) out vec4 second;
void main() { color = vec4(uv, 0.25, 1.0); second = vec4(COLOR_SCALE); }
