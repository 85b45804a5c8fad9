// OpenGL load time: archive -> ready GL programs (statepack::gl, SPIR-V through glShaderBinary and
// glSpecializeShaderARB) against compiling the same pipelines' GLSL source with the driver at run time
// (glShaderSource + glCompileShader + glLinkProgram), on the headless EGL context.
// Usage: gl_load_benchmark <archive.spk> <repeats> "<pipeline>=<shader>[,<shader>...]"...
//   The shader's stage comes from its extension (.vert .tesc .tese .geom .frag .comp); `#include "file"`
//   is resolved next to the including file, as the packager does. Run it through CMake (bench_gl_load),
//   which turns Mesa's on-disk shader cache off so that every run compiles.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "arguments.hpp"
#include "statepack/bootstrap/gl_context.hpp"
#include "statepack/bootstrap/host_tools.hpp"
#include "statepack/gl_dearchiver.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct PipelineSource {
  std::string name;
  std::vector<std::filesystem::path> shaders;
};

GLenum stage_of(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".vert") return GL_VERTEX_SHADER;
  if (ext == ".tesc") return GL_TESS_CONTROL_SHADER;
  if (ext == ".tese") return GL_TESS_EVALUATION_SHADER;
  if (ext == ".geom") return GL_GEOMETRY_SHADER;
  if (ext == ".frag") return GL_FRAGMENT_SHADER;
  if (ext == ".comp") return GL_COMPUTE_SHADER;
  return 0;
}

// The file's text with `#include "x"` lines replaced by x's text, the include extension dropped (the
// driver's GLSL compiler does not know it) and `set = N` removed from layout qualifiers (Vulkan GLSL's;
// glslang ignores it for OpenGL, the driver refuses it). VULKAN stays undefined, as with --opengl.
bool read_source(const std::filesystem::path& path, std::string& out) {
  std::ifstream file(path);
  if (!file)
    return std::fprintf(stderr, "gl_load_benchmark: cannot read %s\n",
                        statepack::bootstrap::printable(path.string()).c_str()),
           false;
  for (std::string line; std::getline(file, line);) {
    if (line.rfind("#extension GL_GOOGLE_include_directive", 0) == 0) continue;
    if (line.rfind("#include \"", 0) == 0) {
      const auto end = line.find('"', 10);
      if (!read_source(path.parent_path() / line.substr(10, end - 10), out)) return false;
      continue;
    }
    static const std::regex set_qualifier(R"(\bset\s*=\s*\d+\s*,\s*)");
    if (line.rfind("layout", 0) == 0) line = std::regex_replace(line, set_qualifier, "");
    out += line;
    out += '\n';
  }
  return true;
}

// The GLSL path: sources read and compiled, programs linked. Returns false on a compile or link error.
bool compile_glsl(const std::vector<PipelineSource>& pipelines, std::vector<GLuint>& programs) {
  for (const auto& p : pipelines) {
    const GLuint program = glCreateProgram();
    programs.push_back(program);
    std::vector<GLuint> shaders;
    for (const auto& path : p.shaders) {
      std::string text;
      if (!read_source(path, text)) return false;
      const GLuint shader = glCreateShader(stage_of(path));
      const char* source = text.c_str();
      glShaderSource(shader, 1, &source, nullptr);
      glCompileShader(shader);
      GLint ok = GL_FALSE;
      glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
      if (ok != GL_TRUE) {
        char log[4096] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        std::fprintf(stderr, "gl_load_benchmark: %s does not compile for OpenGL:\n%s\n",
                     statepack::bootstrap::printable(path.string()).c_str(),
                     statepack::bootstrap::printable(log).c_str());
        glDeleteShader(shader);
        return false;
      }
      glAttachShader(program, shader);
      shaders.push_back(shader);
    }
    glLinkProgram(program);
    for (GLuint s : shaders) glDetachShader(program, s), glDeleteShader(s);
    GLint linked = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (linked != GL_TRUE)
      return std::fprintf(stderr, "gl_load_benchmark: '%s' does not link\n",
                          statepack::bootstrap::printable(p.name).c_str()),
             false;
  }
  return true;
}

// The archive path: loaded, validated, every named pipeline unpacked into a program. The dearchiver
// (which deletes its programs) is returned, so that its destruction is not timed.
std::optional<statepack::gl::Dearchiver> unpack_archive(const char* path,
                                                        const std::vector<PipelineSource>& pipelines) {
  auto archive = statepack::Archive::from_file(path);
  if (!archive)
    return std::fprintf(stderr, "gl_load_benchmark: %s\n",
                        statepack::bootstrap::printable(archive.error().message).c_str()),
           std::nullopt;
  auto dearchiver = statepack::gl::Dearchiver::create();
  if (!dearchiver)
    return std::fprintf(stderr, "gl_load_benchmark: %s\n",
                        statepack::bootstrap::printable(dearchiver.error().message).c_str()),
           std::nullopt;
  if (auto added = dearchiver->add_archive(std::move(*archive)); !added)
    return std::fprintf(stderr, "gl_load_benchmark: %s\n",
                        statepack::bootstrap::printable(added.error().message).c_str()),
           std::nullopt;
  for (const auto& p : pipelines) {
    auto program = dearchiver->unpack_compute(p.name);
    if (!program && program.error().code == statepack::ErrorCode::wrong_type)
      program = dearchiver->unpack_graphics(p.name);
    if (!program)
      return std::fprintf(stderr, "gl_load_benchmark: %s\n",
                          statepack::bootstrap::printable(program.error().message).c_str()),
             std::nullopt;
  }
  glFinish();
  return std::move(dearchiver.value());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(
        stderr,
        "usage: gl_load_benchmark <archive.spk> <repeats> \"<pipeline>=<shader>[,<shader>...]\"...\n");
    return 2;
  }
  const char* archive_path = argv[1];
  const auto repeats_given = statepack::benchmarks::positive_count(argv[2]);
  if (!repeats_given)
    return std::fprintf(stderr, "gl_load_benchmark: repeats must be a number from 1, not '%s'\n",
                        statepack::bootstrap::printable(argv[2]).c_str()),
           2;
  const int repeats = *repeats_given;
  std::vector<PipelineSource> pipelines;
  for (int i = 3; i < argc; ++i) {
    std::string arg = argv[i];
    const auto eq = arg.find('=');
    if (eq == std::string::npos)
      return std::fprintf(stderr, "gl_load_benchmark: expected name=files: %s\n",
                          statepack::bootstrap::printable(argv[i]).c_str()),
             2;
    PipelineSource p{arg.substr(0, eq), {}};
    std::stringstream files(arg.substr(eq + 1));
    for (std::string f; std::getline(files, f, ',');) {
      if (!stage_of(f))
        return std::fprintf(stderr, "gl_load_benchmark: unknown stage of %s\n",
                            statepack::bootstrap::printable(f).c_str()),
               2;
      p.shaders.emplace_back(f);
    }
    pipelines.push_back(std::move(p));
  }

  auto gl = statepack::bootstrap::GlContext::create({.debug = false});
  if (!gl)
    return std::fprintf(stderr, "gl_load_benchmark: %s\n",
                        statepack::bootstrap::printable(gl.error().message).c_str()),
           1;

  std::vector<double> archive_ms, glsl_ms;
  for (int r = 0; r < repeats; ++r) {
    // Alternating which path goes first, so that neither always runs on a warmer process.
    double archive_time = 0, glsl_time = 0;
    auto time_archive = [&] {
      auto t0 = Clock::now();
      auto unpacked = unpack_archive(archive_path, pipelines);
      archive_time = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      return unpacked.has_value();  // its programs are deleted here, untimed
    };
    auto time_glsl = [&] {
      std::vector<GLuint> programs;
      auto t0 = Clock::now();
      const bool compiled = compile_glsl(pipelines, programs);
      glFinish();
      glsl_time = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      for (GLuint p : programs) glDeleteProgram(p);
      return compiled;
    };
    const bool ok = r % 2 == 0 ? time_archive() && time_glsl() : time_glsl() && time_archive();
    if (!ok) return 1;
    archive_ms.push_back(archive_time);
    glsl_ms.push_back(glsl_time);
  }
  const char* cache = std::getenv("MESA_SHADER_CACHE_DISABLE");
  std::printf("OpenGL load time of %zu pipeline(s), median of %d runs, on %s (%s), Mesa shader cache %s\n\n",
              pipelines.size(), repeats, (*gl)->renderer.c_str(), (*gl)->version.c_str(),
              cache && std::string(cache) == "true" ? "off" : "on");
  std::printf("| path | first run (ms) | median (ms) |\n|---|---|---|\n");
  std::printf("| archive -> programs (SPIR-V, statepack::gl) | %.2f | %.2f |\n", archive_ms[0],
              median(archive_ms));
  std::printf("| GLSL source compiled by the driver | %.2f | %.2f |\n", glsl_ms[0], median(glsl_ms));
  std::printf("| ratio (GLSL / archive, medians) | | %.2fx |\n", median(glsl_ms) / median(archive_ms));
  return 0;
}
