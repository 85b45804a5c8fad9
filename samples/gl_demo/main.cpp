// gl_demo: loads a statepack archive packed with --opengl, unpacks every OpenGL program on a headless
// OpenGL 4.5 context (EGL surfaceless: Mesa's llvmpipe on a machine without a GPU), prints what it
// created, and runs the compute program once to show it works. Links libstatepack_gl and the dearchiver
// only: no shader compiler, and the driver compiles no GLSL.
#include <cstdio>
#include <string>
#include <vector>

#include "statepack/bootstrap/gl_context.hpp"
#include "statepack/bootstrap/host_tools.hpp"
#include "statepack/gl_dearchiver.hpp"

namespace {

// Names and paths come from the archive or the command line: escaped before they reach the terminal.
using statepack::bootstrap::printable;

int fail(const std::string& what, const statepack::Error& e) {
  std::fprintf(stderr, "gl_demo: %s: %s (%s)\n", printable(what).c_str(), printable(e.message).c_str(),
               statepack::to_string(e.code));
  return 1;
}

// Fills a buffer with the compute program and prints the first values (as unpack_demo does on Vulkan;
// Vulkan's push constants are the uniform block `Params` here).
int run_fill_buffer(const statepack::gl::Program& program) {
  const statepack::gl::Binding* values = program.find_binding("Values");
  const statepack::gl::Binding* params = program.find_binding("Params");
  if (!values || !params) return std::fprintf(stderr, "gl_demo: 'Values' or 'Params' binding missing\n"), 1;
  constexpr uint32_t kCount = 16;
  const uint32_t uniforms[4] = {kCount, 3, 1, 0};  // count, multiplier, offset (std140: padded to 16 bytes)
  GLuint buffers[2] = {};
  glCreateBuffers(2, buffers);
  glNamedBufferStorage(buffers[0], kCount * sizeof(uint32_t), nullptr, 0);
  glNamedBufferStorage(buffers[1], sizeof uniforms, uniforms, 0);
  glUseProgram(program.program);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, values->binding, buffers[0]);
  glBindBufferBase(GL_UNIFORM_BUFFER, params->binding, buffers[1]);
  glDispatchCompute(1, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  uint32_t out[kCount] = {};
  glGetNamedBufferSubData(buffers[0], 0, sizeof out, out);
  glUseProgram(0);
  glDeleteBuffers(2, buffers);
  std::printf("  ran '%s': values =", printable(program.name).c_str());
  for (uint32_t v : out) std::printf(" %u", v);
  std::printf("\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = argc > 1 ? argv[1] : STATEPACK_DEFAULT_GL_ARCHIVE;
  if (path == "-h" || path == "--help") {
    std::printf("usage: gl_demo [archive.spk]  (packed with --opengl)\n  default: %s\n",
                STATEPACK_DEFAULT_GL_ARCHIVE);
    return 0;
  }
  // One archive at most, and no options but --help: anything else is a usage error (exit 2), not a
  // file name or an argument silently dropped.
  if (argc > 2 || path.starts_with("-")) {
    std::fprintf(
        stderr,
        "gl_demo: error: unexpected argument '%s'\nusage: gl_demo [archive.spk]  (packed with --opengl)\n",
        printable(argc > 2 ? argv[2] : path).c_str());
    return 2;
  }
  auto archive = statepack::Archive::from_file(path);
  if (!archive) return fail("load", archive.error());
  std::printf("archive %s: format v%u, content version %u\n", printable(path).c_str(),
              archive->format_version(), archive->content_version());

  auto gl = statepack::bootstrap::GlContext::create();
  if (!gl) return fail("OpenGL", gl.error());
  std::printf("OpenGL: %s (%s), debug output on\n", printable((*gl)->renderer).c_str(),
              printable((*gl)->version).c_str());

  int status = 0;
  {
    auto dearchiver = statepack::gl::Dearchiver::create();
    if (!dearchiver) return fail("gl dearchiver", dearchiver.error());
    if (auto added = dearchiver->add_archive(std::move(*archive)); !added)
      return fail("add archive", added.error());
    for (const auto& name : dearchiver->program_names()) {
      auto program = dearchiver->unpack_compute(name);
      if (!program && program.error().code == statepack::ErrorCode::wrong_type)
        program = dearchiver->unpack_graphics(name);
      if (!program) return fail("unpack '" + name + "'", program.error());
      const statepack::gl::Program& p = **program;
      std::printf("unpacked '%s' (%s): GL program %u", printable(p.name).c_str(),
                  p.compute ? "compute" : "graphics", p.program);
      if (!p.compute)
        std::printf(", %u render target(s), cull %s, depth test %s", p.state.color_count,
                    p.state.cull_enable ? "on" : "off", p.state.depth_test ? "on" : "off");
      std::printf("\n");
      for (const auto& b : p.bindings)
        std::printf("  %s binding %u: '%s' (x%u)\n", statepack::gl::to_string(b.kind), b.binding,
                    printable(b.name).c_str(), b.count);
      if (p.compute && name == "Fill Buffer PSO") status |= run_fill_buffer(p);
    }
  }  // the programs go while the context is current
  auto messages = (*gl)->error_messages();
  for (const auto& m : messages) std::fprintf(stderr, "%s\n", printable(m).c_str());
  std::printf("%zu GL error message(s)\n", messages.size());
  return status != 0 || !messages.empty() ? 1 : 0;
}
