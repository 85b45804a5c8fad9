// gl::Dearchiver: finds archived GL pipelines by name and links each into a program once, from the
// archive's SPIR-V (glShaderBinary + glSpecializeShaderARB); no GLSL reaches the driver.
#include "statepack/gl_dearchiver.hpp"

#include "support/failure.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <set>
#include <utility>

#include "format/archive_file.hpp"
#include "format/archive_format.hpp"
#include "format/spirv_walk.hpp"
#include "gl_state.hpp"
#include "runtime/api_guard.hpp"
#include "runtime/archive_access.hpp"
#include "support/printable.hpp"
#include "support/suggest.hpp"

namespace statepack::gl {
using statepack::detail::api_guard;  // the runtime's internals this library shares
using statepack::detail::did_you_mean;

const char* to_string(Binding::Kind kind) {
  return format::gl_namespace_name(uint32_t(kind));  // Binding::Kind has the archive's numbering
}

const Binding* Program::find_binding(std::string_view resource_name) const {
  for (const auto& b : bindings)
    if (b.name == resource_name) return &b;
  return nullptr;
}

namespace {

// A GL object deleted on scope exit unless released (error paths leave nothing behind).
template <void (*Delete)(GLuint)>
class GlName {
 public:
  explicit GlName(GLuint name) : name_(name) {}
  GlName(GlName&& other) noexcept : name_(other.release()) {}
  GlName& operator=(GlName&&) = delete;
  ~GlName() {
    if (name_) Delete(name_);
  }
  GLuint get() const { return name_; }
  GLuint release() { return std::exchange(name_, 0); }

 private:
  GLuint name_;
};
void delete_shader(GLuint name) {
  glDeleteShader(name);
}
void delete_program(GLuint name) {
  glDeleteProgram(name);
}

const char* error_name(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    default:
      return "an OpenGL error";
  }
}

// The shader's info log; when the driver wrote none, the error the failing call raised (e.g.
// GL_INVALID_VALUE for a specialization constant id the module does not have).
std::string shader_log(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 0)), '\0');
  if (length > 0) glGetShaderInfoLog(shader, length, nullptr, log.data());
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  if (!log.empty()) return log;
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) return std::string("no info log; the call raised ") + error_name(error);
  return "the driver gave no info log";
}

std::string program_log(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 0)), '\0');
  if (length > 0) glGetProgramInfoLog(program, length, nullptr, log.data());
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  return log.empty() ? "the driver gave no info log" : log;
}

const char* kind_name(format::PipelineKind kind) {
  return kind == format::PipelineKind::compute ? "compute" : "graphics";
}

}  // namespace

// What a program was made from, to compare with a new build (reload): the pipeline's record with its
// shaders' places in the archive cleared, and a hash of each shader's SPIR-V.
struct ProgramSource {
  format::GlPipeline record;
  std::vector<uint64_t> blobs;
  size_t archive = 0;  // the added archive (its place in the list) it was made from
  bool same_content(const ProgramSource& o) const { return record == o.record && blobs == o.blobs; }
};

ProgramSource source_of(const format::Contents& contents, const format::GlPipeline& pipeline,
                        size_t archive) {
  ProgramSource out{pipeline, {}, archive};
  for (auto& shader : out.record.shaders) {
    const auto words = contents.spirv[shader.blob];
    out.blobs.push_back(
        format::hash_bytes({reinterpret_cast<const uint8_t*>(words.data()), words.size_bytes()}));
    shader.blob = 0;
  }
  return out;
}

struct Dearchiver::State {
  detail::Extensions extensions;
  std::vector<Archive> archives;
  std::deque<Program> programs;  // stable addresses
  std::map<std::string, const Program*, std::less<>> by_name;
  std::map<const Program*, ProgramSource> sources;  // every program, for reload
  std::vector<GLuint> retired;                      // programs a reload replaced, until destroy_retired
  uint64_t generation = 0;

  ~State() {
    for (const auto& p : programs) glDeleteProgram(p.program);
    for (GLuint p : retired) glDeleteProgram(p);
  }

  const format::Contents& contents(size_t archive) const {
    return statepack::detail::ArchiveAccess::contents(archives[archive]);
  }

  // Every GL pipeline name once (a name in several archives resolves to the earliest).
  std::vector<std::string> gl_names() const {
    std::vector<std::string> names;
    std::set<std::string_view> seen;  // linear-log: archives may hold many pipelines
    for (size_t i = 0; i < archives.size(); ++i)
      for (const auto& p : contents(i).gl_pipelines)
        if (seen.insert(p.name).second) names.push_back(p.name);
    return names;
  }

  struct Found {
    const format::Contents* contents;
    const format::GlPipeline* pipeline;
    size_t archive;
  };

  Result<Found> find(std::string_view name, format::PipelineKind kind) const {
    for (size_t i = 0; i < archives.size(); ++i) {
      const format::GlPipeline* it = format::find_by_name(contents(i).gl_pipelines, name);
      if (!it) continue;
      if (it->kind != kind)
        return statepack::detail::failure(ErrorCode::wrong_type,
                                          "pipeline '" + std::string(name) + "' is a " + kind_name(it->kind) +
                                              " pipeline, not a " + kind_name(kind) + " pipeline");
      return Found{&contents(i), it, i};
    }
    // Packed, but for Vulkan only?
    for (size_t i = 0; i < archives.size(); ++i)
      for (const auto& p : contents(i).pipelines)
        if (p.name == name)
          return statepack::detail::failure(
              ErrorCode::missing_backend,
              "pipeline '" + std::string(name) + "' has no OpenGL version in its archive (only Vulkan)");
    return statepack::detail::failure(ErrorCode::not_found, "no OpenGL pipeline named '" + std::string(name) +
                                                                "' in " + std::to_string(archives.size()) +
                                                                " loaded archive(s)" +
                                                                did_you_mean(name, gl_names()));
  }

  // glCreateShader + glShaderBinary(SPIR-V) + glSpecializeShaderARB, checked.
  Result<GLuint> create_shader(const format::GlPipeline& pipeline, const format::GlShader& shader,
                               const format::Contents& contents) const {
    const std::string what = "pipeline '" + pipeline.name + "': " + spirv::stage_name(shader.stage) +
                             " shader '" + shader.name + "'";
    const GLenum type = detail::shader_type(shader.stage);
    if (type == 0)
      return statepack::detail::failure(
          ErrorCode::unsupported,
          what + ": stage " + std::to_string(shader.stage) + " is not an OpenGL stage");
    if (shader.blob >= contents.spirv.size())  // the decoder checks this; a cheap second look
      return statepack::detail::failure(
          ErrorCode::corrupt, what + ": SPIR-V blob " + std::to_string(shader.blob) + " does not exist");
    std::vector<GLuint> ids, values;
    for (const auto& c : pipeline.constants) {
      if (c.stage != shader.stage) continue;
      if (c.size != 4)
        return statepack::detail::failure(
            ErrorCode::unsupported, what + ": specialization constant '" + c.name + "' (id " +
                                        std::to_string(c.constant_id) + ") has " + std::to_string(c.size) +
                                        " bytes; glSpecializeShader takes 32-bit values only");
      ids.push_back(c.constant_id);
      values.push_back(GLuint(c.value & 0xFFFFFFFFu));
    }
    const auto& spirv = contents.spirv[shader.blob];
    GlName<delete_shader> name(glCreateShader(type));
    if (name.get() == 0)
      return statepack::detail::failure(ErrorCode::gl_error, what + ": glCreateShader failed");
    const GLuint handle = name.get();
    // Flags left by earlier calls would be read as this shader's by shader_log: cleared first (GL errors
    // are sticky until read; documented in gl_dearchiver.hpp).
    while (glGetError() != GL_NO_ERROR) {
    }
    // A binary the driver refuses leaves the shader unspecializable: the compile status below reports it.
    glShaderBinary(1, &handle, GL_SHADER_BINARY_FORMAT_SPIR_V_ARB, spirv.data(), GLsizei(spirv.size_bytes()));
    glSpecializeShaderARB(handle, shader.entry_point.c_str(), GLuint(ids.size()), ids.data(), values.data());
    GLint compiled = GL_FALSE;
    glGetShaderiv(handle, GL_COMPILE_STATUS, &compiled);
    if (compiled != GL_TRUE)
      return statepack::detail::failure(ErrorCode::gl_error, what + ": glSpecializeShader (entry point '" +
                                                                 shader.entry_point +
                                                                 "') failed: " + shader_log(handle));
    return name.release();
  }

  // A linked program and its state for an archived pipeline (nothing kept: the caller does that).
  Result<Program> make_program(const Found& found, format::PipelineKind kind) const {
    const format::GlPipeline& pipeline = *found.pipeline;

    Program out;
    out.name = pipeline.name;
    out.compute = kind == format::PipelineKind::compute;
    if (!out.compute) {
      auto state = detail::translate_state(pipeline.graphics, pipeline.name, extensions);
      if (!state) return state.error();
      out.state = std::move(*state);
      auto vertex_input = detail::translate_vertex_input(pipeline.graphics, pipeline.name);
      if (!vertex_input) return vertex_input.error();
      out.vertex_input = std::move(*vertex_input);
    }
    for (const auto& b : pipeline.bindings) {
      if (b.kind >= format::kGlNamespaceCount)
        return statepack::detail::failure(ErrorCode::corrupt, "pipeline '" + pipeline.name + "': binding '" +
                                                                  b.name + "' has unknown namespace " +
                                                                  std::to_string(b.kind));
      out.bindings.push_back({b.name, Binding::Kind(b.kind), b.binding, b.count, b.stages});
    }
    if (pipeline.shaders.empty())
      return statepack::detail::failure(ErrorCode::corrupt,
                                        "pipeline '" + pipeline.name + "' has no shaders");

    std::vector<GlName<delete_shader>> shaders;
    shaders.reserve(pipeline.shaders.size());
    for (const auto& s : pipeline.shaders) {
      auto shader = create_shader(pipeline, s, *found.contents);
      if (!shader) return shader.error();
      shaders.emplace_back(*shader);
    }
    GlName<delete_program> program(glCreateProgram());
    if (program.get() == 0)
      return statepack::detail::failure(ErrorCode::gl_error,
                                        "pipeline '" + pipeline.name + "': glCreateProgram failed");
    for (const auto& s : shaders) glAttachShader(program.get(), s.get());
    glLinkProgram(program.get());
    GLint linked = GL_FALSE;
    glGetProgramiv(program.get(), GL_LINK_STATUS, &linked);
    for (const auto& s : shaders) glDetachShader(program.get(), s.get());  // the program keeps its code
    if (linked != GL_TRUE)
      return statepack::detail::failure(
          ErrorCode::gl_error,
          "pipeline '" + pipeline.name + "': glLinkProgram failed: " + program_log(program.get()));
    out.program = program.release();
    return out;
  }

  Result<const Program*> unpack(std::string_view name, format::PipelineKind kind) {
    if (epoxy_gl_version() == 0)  // no context current on this thread (create() checked one was)
      return statepack::detail::failure(
          ErrorCode::unsupported,
          "unpacking '" + std::string(name) + "' needs an OpenGL context current on this thread");
    if (auto it = by_name.find(name); it != by_name.end()) {
      const bool compute = kind == format::PipelineKind::compute;
      if (it->second->compute != compute)
        return statepack::detail::failure(
            ErrorCode::wrong_type, "pipeline '" + std::string(name) + "' is a " +
                                       (it->second->compute ? "compute" : "graphics") + " pipeline, not a " +
                                       kind_name(kind) + " pipeline");
      return it->second;
    }
    auto found = find(name, kind);
    if (!found) return found.error();
    auto made = make_program(*found, kind);
    if (!made) return made.error();
    programs.push_back(std::move(*made));
    const Program* kept = &programs.back();
    by_name.emplace(kept->name, kept);
    sources.emplace(kept, source_of(*found->contents, *found->pipeline, found->archive));
    return kept;
  }

  // Re-creates the programs whose pipeline the new build changed, in the same Program (docs/api.md).
  Result<ReloadReport> reload(Archive next, const ReloadOptions& options) {
    if (epoxy_gl_version() == 0)
      return statepack::detail::failure(
          ErrorCode::unsupported, "gl::Dearchiver::reload needs an OpenGL context current on this thread");
    if (options.archive >= archives.size())
      return statepack::detail::failure(ErrorCode::invalid_argument,
                                        "gl::Dearchiver::reload: ReloadOptions::archive is " +
                                            std::to_string(options.archive) + ", but " +
                                            std::to_string(archives.size()) + " archive(s) were added");
    const format::Contents& incoming = statepack::detail::ArchiveAccess::contents(next);
    if (incoming.gl_pipelines.empty())
      return statepack::detail::failure(ErrorCode::missing_backend,
                                        "gl::Dearchiver::reload: the new archive holds no OpenGL pipelines");
    if (auto checked = format::check_opengl(incoming, "gl::Dearchiver::reload"); !checked)
      return checked.error();
    if (!options.allow_content_version_change &&
        next.content_version() != archives[options.archive].content_version())
      return statepack::detail::failure(ErrorCode::content_version_mismatch,
                                        "gl::Dearchiver::reload: the new archive's content version is " +
                                            std::to_string(next.content_version()) +
                                            ", the one it replaces has " +
                                            std::to_string(archives[options.archive].content_version()) +
                                            " (ReloadOptions::allow_content_version_change accepts it)");
    // The programs made from the replaced archive; the others are not its.
    const format::Contents* replaced = &contents(options.archive);
    std::vector<Program*> affected;
    for (Program& p : programs) {
      auto named = by_name.find(p.name);
      if (named == by_name.end() || named->second != &p) continue;  // removed by an earlier reload
      if (sources.at(&p).archive == options.archive) affected.push_back(&p);
    }
    ReloadReport report;
    for (const auto& g : incoming.gl_pipelines)
      if (!format::find_by_name(replaced->gl_pipelines, g.name)) report.added.push_back(g.name);
    archives[options.archive] = std::move(next);        // the programs keep no pointer into the old one
    retired.reserve(retired.size() + affected.size());  // so that retiring a program never throws
    for (Program* p : affected) reload_program(*p, options.archive, report);
    if (!report.recreated.empty()) ++generation;
    report.generation = generation;
    return report;
  }

  void reload_program(Program& p, size_t archive, ReloadReport& report) {
    const auto kind = p.compute ? format::PipelineKind::compute : format::PipelineKind::graphics;
    // Looked up in the new build only: a namesake in another archive is not this program's successor.
    const format::GlPipeline* it = format::find_by_name(contents(archive).gl_pipelines, p.name);
    if (!it || it->kind != kind) {
      report.removed.push_back(p.name);
      by_name.erase(p.name);  // the Program stays the application's
      return;
    }
    const Found now{&contents(archive), it, archive};
    ProgramSource& was = sources.at(&p);
    ProgramSource next = source_of(*now.contents, *now.pipeline, archive);
    if (next.same_content(was)) {
      report.kept.push_back(p.name);
      return;
    }
    const ObjectInfo info{p.name, p.compute ? ObjectKind::compute_pipeline : ObjectKind::graphics_pipeline};
    if (next.record.bindings != was.record.bindings) {
      report.failures.push_back(
          {info, statepack::detail::failure(
                     ErrorCode::layout_changed,
                     "pipeline '" + statepack::detail::printable(p.name) +
                         "': its bindings changed (a resource's name, namespace, binding, count or stages), "
                         "which the application binds its buffers and textures by; the old program stays "
                         "(unpack it in a new Dearchiver to use the new bindings)")});
      return;
    }
    auto made = make_program(now, kind);
    if (!made) {
      report.failures.push_back({info, made.error()});
      return;
    }
    // The bindings are equal: only the program and its state change, so pointers into the Program (its
    // bindings, found by name) stay valid.
    retired.push_back(p.program);  // reserved: cannot throw
    p.program = made->program;
    p.state = made->state;
    p.vertex_input = std::move(made->vertex_input);
    was = std::move(next);
    report.recreated.push_back(p.name);
  }
};

Dearchiver::Dearchiver(std::unique_ptr<State> state) : state_(std::move(state)) {}
Dearchiver::Dearchiver(Dearchiver&&) noexcept = default;
Dearchiver& Dearchiver::operator=(Dearchiver&&) noexcept = default;
Dearchiver::~Dearchiver() = default;

Result<Dearchiver> Dearchiver::create() {
  return api_guard("gl::Dearchiver::create", [&]() -> Result<Dearchiver> {
    const int version = epoxy_gl_version();  // 45 for 4.5; 0 without a current context
    if (version == 0)
      return statepack::detail::failure(
          ErrorCode::unsupported,
          "gl::Dearchiver::create: no OpenGL context is current on the calling thread");
    if (!epoxy_is_desktop_gl())
      return statepack::detail::failure(
          ErrorCode::unsupported, "gl::Dearchiver::create: the current context is OpenGL ES, not OpenGL");
    if (version < 45)
      return statepack::detail::failure(
          ErrorCode::unsupported, "gl::Dearchiver::create: needs a current OpenGL 4.5 context; this one is " +
                                      std::to_string(version / 10) + "." + std::to_string(version % 10));
    if (!epoxy_has_gl_extension("GL_ARB_gl_spirv"))
      return statepack::detail::failure(
          ErrorCode::unsupported,
          "gl::Dearchiver::create: the current context lacks GL_ARB_gl_spirv (SPIR-V shaders)");
    auto state = std::make_unique<State>();
    state->extensions.polygon_offset_clamp =
        version >= 46 || epoxy_has_gl_extension("GL_ARB_polygon_offset_clamp");
    return Dearchiver(std::move(state));
  });
}

Result<void> Dearchiver::add_archive(Archive archive) {
  return api_guard("gl::Dearchiver::add_archive", [&]() -> Result<void> {
    const auto& contents = statepack::detail::ArchiveAccess::contents(archive);
    if (contents.gl_pipelines.empty())
      return statepack::detail::failure(
          ErrorCode::missing_backend,
          "gl::Dearchiver::add_archive: the archive holds no OpenGL pipelines (pack it with "
          "`statepack --opengl`)");
    // Archive::from_* checked the Vulkan part only; the OpenGL block is checked here, where it is used.
    if (auto checked = format::check_opengl(contents, "gl::Dearchiver::add_archive"); !checked)
      return checked.error();
    state_->archives.push_back(std::move(archive));
    return {};
  });
}

Result<ReloadReport> Dearchiver::reload(Archive archive, const ReloadOptions& options) {
  return api_guard("gl::Dearchiver::reload",
                   [&]() -> Result<ReloadReport> { return state_->reload(std::move(archive), options); });
}

uint64_t Dearchiver::reload_generation() const {
  return state_->generation;
}

size_t Dearchiver::destroy_retired() {
  for (GLuint p : state_->retired) glDeleteProgram(p);
  const size_t deleted = state_->retired.size();
  state_->retired.clear();
  return deleted;
}

std::vector<std::string> Dearchiver::program_names() const {
  return state_->gl_names();
}

Result<const Program*> Dearchiver::unpack_graphics(std::string_view name) {
  return api_guard("gl::Dearchiver::unpack_graphics", [&]() -> Result<const Program*> {
    return state_->unpack(name, format::PipelineKind::graphics);
  });
}

Result<const Program*> Dearchiver::unpack_compute(std::string_view name) {
  return api_guard("gl::Dearchiver::unpack_compute", [&]() -> Result<const Program*> {
    return state_->unpack(name, format::PipelineKind::compute);
  });
}

}  // namespace statepack::gl
