#version 450
// Bindings here are deliberately "wrong": the packager patches them to the signature's layout.
layout(set = 5, binding = 9) uniform Constants { vec4 tint; } constants;
layout(set = 5, binding = 3) uniform sampler2D g_Texture;
layout(location = 0) in vec2 uv;
layout(location = 0) out vec4 color;
void main() { color = texture(g_Texture, uv) * constants.tint; }
