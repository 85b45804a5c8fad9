// libstatepack_gl — unpacks the OpenGL backend of statepack archives into linked GL programs.
//
//   // An OpenGL 4.5 core context with GL_ARB_gl_spirv is current on this thread.
//   auto archive = statepack::Archive::from_file("scene.spk");      // packed with `statepack --opengl`
//   auto gl = statepack::gl::Dearchiver::create();
//   if (!gl || !gl->add_archive(std::move(*archive))) return ...;
//   auto program = gl->unpack_graphics("Gradient PSO");
//   if (!program) return fail(program.error());                     // names the pipeline and why
//   glUseProgram((*program)->program);
//   (*program)->state.apply();                                      // blend, raster, depth-stencil
//   glDrawArrays((*program)->state.primitive_mode, 0, 3);
//
// Each archived GL pipeline becomes one linked program, made from the archive's SPIR-V with
// glShaderBinary(GL_SHADER_BINARY_FORMAT_SPIR_V_ARB) and glSpecializeShaderARB (its entry points and
// specialization constants): no shader compiler is linked, and the driver compiles no GLSL.
//
// Threading: OpenGL calls go to the context current on the calling thread. Every member function, the
// destructor included, must be called with the same context (or one sharing its objects) current, from
// one thread at a time (unpacking without a current context is an `unsupported` error). The Dearchiver
// owns the programs it created and deletes them with itself. Unpacking clears OpenGL's error flags
// (glGetError) before creating each shader, so that the driver's errors are reported as its own.
//
// Conventions: the SPIR-V is the Vulkan-style shader compiled for OpenGL, so clip-space z runs 0..1 and
// the same vertex positions land on the same framebuffer rows as on Vulkan. FixedFunctionState::apply()
// sets glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) (depth as on Vulkan); with GL's lower-left window
// origin, the row that Vulkan stores first (framebuffer y = 0, clip y = -1) is also the first row
// glReadPixels returns, so the two images' bytes match without flipping. Displayed on screen, GL's
// image is upside down relative to Vulkan's; present by blitting with flipped y if that matters.
// Winding follows from that: GL computes a polygon's area with y up, Vulkan with y down, so the same
// vertices wind the other way. The archive's VkFrontFace is therefore inverted for glFrontFace
// (VK_FRONT_FACE_CLOCKWISE becomes GL_CCW), which culls exactly the triangles Vulkan culls.
//
// The header needs no GL header: the types below are OpenGL's own (khrplatform's) under the same names,
// so values pass to and from epoxy, glad or GL/gl.h unchanged; include whichever loader you use.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "statepack/dearchiver.hpp"  // Archive
#include "statepack/result.hpp"

namespace statepack::gl {

using GLenum = unsigned int;
using GLuint = unsigned int;
using GLint = int;
using GLsizei = int;
// The enum values the defaults below start from (OpenGL's registry values; gl_state.cpp checks them
// against the GL header it is built with).
namespace enums {
inline constexpr GLenum kZero = 0, kOne = 1, kTriangles = 0x0004, kLess = 0x0201, kAlways = 0x0207,
                        kBack = 0x0405, kCcw = 0x0901, kFloat = 0x1406, kFill = 0x1B02, kKeep = 0x1E00,
                        kFuncAdd = 0x8006;
}  // namespace enums

inline constexpr uint32_t kMaxColorTargets = 8;

struct BlendTarget {
  bool enable = false;
  GLenum src_color = enums::kOne, dst_color = enums::kZero, color_op = enums::kFuncAdd;
  GLenum src_alpha = enums::kOne, dst_alpha = enums::kZero, alpha_op = enums::kFuncAdd;
  std::array<bool, 4> write_mask{true, true, true, true};  // glColorMaski: r, g, b, a
};

struct StencilFace {
  GLenum fail_op = enums::kKeep, depth_fail_op = enums::kKeep, pass_op = enums::kKeep;
  GLenum func = enums::kAlways;
};

// A graphics pipeline's fixed-function state in GL terms, translated from the archive. Viewport and
// scissor are the application's (dynamic on Vulkan too); so are the two values Vulkan also leaves
// dynamic, `stencil_reference` and `blend_color`, which apply() sets from these fields.
struct FixedFunctionState {
  GLenum primitive_mode = enums::kTriangles;  // for glDraw*
  GLint patch_vertices = 0;                   // GL_PATCHES only: glPatchParameteri(GL_PATCH_VERTICES, ...)

  // Rasterizer
  bool cull_enable = false;
  GLenum cull_face = enums::kBack;     // glCullFace
  GLenum front_face = enums::kCcw;     // glFrontFace: the archive's VkFrontFace, inverted (see above)
  GLenum polygon_mode = enums::kFill;  // glPolygonMode(GL_FRONT_AND_BACK, ...)
  bool depth_clamp = false;            // GL_DEPTH_CLAMP (the notation's DepthClipEnable = false)
  bool depth_bias_enable = false;
  float depth_bias_constant = 0, depth_bias_slope = 0, depth_bias_clamp = 0;  // glPolygonOffset(Clamp)

  // Depth-stencil
  bool depth_test = false;
  bool depth_write = false;
  GLenum depth_func = enums::kLess;
  bool stencil_test = false;
  GLuint stencil_read_mask = 0xFF, stencil_write_mask = 0xFF;
  StencilFace stencil_front, stencil_back;
  GLint stencil_reference = 0;  // dynamic on Vulkan: set it before apply()

  // Multisample
  GLuint sample_mask = 0xFFFFFFFFu;  // glSampleMaski(0, ...); GL_SAMPLE_MASK enabled when not all ones
  bool alpha_to_coverage = false;
  GLuint samples = 1;  // what the archive's targets have (the framebuffer decides in GL)

  // Blend, per render target
  uint32_t color_count = 0;
  std::array<BlendTarget, kMaxColorTargets> blend{};
  std::array<float, 4> blend_color{0, 0, 0, 0};  // dynamic on Vulkan: set it before apply()

  // Which way clip-space y points for the shaders. vulkan: the archive's own convention, the same rows as
  // a Vulkan viewport of positive height. up: Direct3D's, which Diligent's shaders are written for (its
  // Vulkan backend gives them a viewport of negative height): the OpenGL equal of that flipped viewport.
  enum class ClipY { vulkan, up };

  // Sets all of the above in the current context (glEnable/glDisable, glBlendFuncSeparatei, ...), plus
  // glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) (GL_UPPER_LEFT for ClipY::up, with front faces as that
  // origin sees them) and GL_FRAMEBUFFER_SRGB (sRGB targets encode, as on Vulkan). Leaves viewport,
  // scissor, bound objects and targets >= color_count alone.
  void apply(ClipY clip_y = ClipY::vulkan) const;
};

// A graphics pipeline's vertex input as a vertex array object's format (GL 4.3 vertex attribute
// binding): configure() sets it on a VAO; the application binds its buffers with
// glVertexArrayVertexBuffer(vao, binding, buffer, offset, stride) using the strides listed here.
struct VertexInput {
  enum class Path { float_, integer, double_ };  // glVertexArrayAttribFormat / IFormat / LFormat
  struct Attribute {
    GLuint location = 0, binding = 0;
    GLint size = 4;  // components, or GL_BGRA for B8G8R8A8 and A2R10G10B10 formats
    GLenum type = enums::kFloat;
    bool normalized = false;
    Path path = Path::float_;
    GLuint offset = 0;  // relative offset within the binding's element
  };
  struct BufferBinding {
    GLuint binding = 0;
    GLsizei stride = 0;
    GLuint divisor = 0;  // 1 for per-instance data (VK_VERTEX_INPUT_RATE_INSTANCE)
  };
  std::vector<Attribute> attributes;
  std::vector<BufferBinding> bindings;

  // Enables and formats every attribute of `vertex_array` and sets the bindings' divisors.
  void configure(GLuint vertex_array) const;
};

struct Binding {
  // The GL binding namespace: glBindBufferBase(GL_UNIFORM_BUFFER / GL_SHADER_STORAGE_BUFFER, binding, ...),
  // glBindTextureUnit(binding, ...), glBindImageTexture(binding, ...).
  enum class Kind : uint32_t { uniform_buffer = 0, storage_buffer = 1, texture = 2, image = 3 };
  std::string name;  // the shader's resource name (block or variable)
  Kind kind = Kind::uniform_buffer;
  uint32_t binding = 0;
  uint32_t count = 1;   // array elements, on consecutive bindings from `binding`
  uint32_t stages = 0;  // VkShaderStageFlags of the stages that use it
};

STATEPACK_API const char* to_string(Binding::Kind kind);

struct Program {
  std::string name;  // the pipeline's
  GLuint program = 0;
  bool compute = false;
  FixedFunctionState state;  // graphics programs only
  VertexInput vertex_input;  // graphics programs only; empty when the shaders read no vertex buffers
  std::vector<Binding> bindings;
  const Binding* find_binding(std::string_view resource_name) const;  // nullptr when absent
};

class STATEPACK_API Dearchiver {
 public:
  // Needs a current OpenGL 4.5 (or later) core or compatibility context with GL_ARB_gl_spirv; errors
  // with `unsupported` otherwise.
  static Result<Dearchiver> create();

  Dearchiver(Dearchiver&&) noexcept;
  Dearchiver& operator=(Dearchiver&&) noexcept;
  ~Dearchiver();  // deletes every program it created (the context must be current)

  // Adds an archive; names resolve across all added archives, the earliest added winning. An archive
  // without OpenGL pipelines (packed without --opengl) is refused with `missing_backend`.
  Result<void> add_archive(Archive archive);

  // Creates (once) and returns the linked program of a pipeline; unpacking the same name again returns
  // the same Program. The pointer stays valid for the Dearchiver's lifetime. Errors: not_found (with
  // suggestions), wrong_type, missing_backend (the pipeline was packed for Vulkan only), unsupported,
  // gl_error (a shader did not specialize or the program did not link: the driver's info log).
  Result<const Program*> unpack_graphics(std::string_view name);
  Result<const Program*> unpack_compute(std::string_view name);

  // The names of every GL pipeline of every added archive.
  std::vector<std::string> program_names() const;

  // Replaces an added archive with a new build of it (statepack::Dearchiver::reload's OpenGL twin,
  // docs/api.md): every program unpacked from it whose shaders or state changed is linked again from the
  // new archive and written into the same Program (its `program` name changes; re-read it after a
  // reload); unchanged ones stay. A change of a program's bindings is a `layout_changed` failure, and
  // the old program stays, as for any failure. options.patch is not used (OpenGL programs are not
  // patched). Needs the context current.
  Result<ReloadReport> reload(Archive archive, const ReloadOptions& options = {});
  uint64_t reload_generation() const;  // reloads that re-created a program
  // Deletes the programs reloads replaced (OpenGL defers a delete while a program is in use, but
  // commands may still reference it); returns how many.
  size_t destroy_retired();

 private:
  struct State;
  explicit Dearchiver(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace statepack::gl
