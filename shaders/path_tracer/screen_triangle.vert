#version 450
// A triangle covering the screen; the path tracer's fragment shaders work from gl_FragCoord alone.
// gl_VertexIndex is Vulkan's name, gl_VertexID OpenGL's (--opengl compiles without VULKAN defined).
#ifdef VULKAN
#define VERTEX_ID gl_VertexIndex
#else
#define VERTEX_ID gl_VertexID
#endif
void main() {
  vec2 corner = vec2((VERTEX_ID << 1) & 2, VERTEX_ID & 2);
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
