#version 450
layout(location = 0) in vec3 position;
layout(location = 1) in vec2 texcoord;
layout(location = 2) in vec4 instance_offset;
layout(location = 0) out vec2 uv;
layout(set = 0, binding = 0) uniform Camera { mat4 view_proj; } camera;
void main() {
  uv = texcoord;
  gl_Position = camera.view_proj * vec4(position + instance_offset.xyz, 1.0);
}
