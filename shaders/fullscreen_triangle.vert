#version 450
// One triangle that covers the screen; uv runs 0..1 across the visible part.
// gl_VertexIndex is Vulkan's name, gl_VertexID OpenGL's (--opengl compiles without VULKAN defined).
#ifdef VULKAN
#define VERTEX_ID gl_VertexIndex
#else
#define VERTEX_ID gl_VertexID
#endif
layout(location = 0) out vec2 out_uv;

void main() {
  vec2 corner = vec2((VERTEX_ID << 1) & 2, VERTEX_ID & 2);  // (0,0) (2,0) (0,2)
  out_uv = corner;
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
