#version 450
// Two vertex buffers: positions in slot 0; color (RGBA8_UNORM) and an id (R32_UINT) in slot 1.
layout(location = 0) in vec2 position;
layout(location = 1) in vec4 color;
layout(location = 2) in uint id;
layout(location = 0) out vec4 out_color;
layout(location = 1) flat out uint out_id;
void main() {
  out_color = color;
  out_id = id;
  gl_Position = vec4(position, 0.0, 1.0);
}
