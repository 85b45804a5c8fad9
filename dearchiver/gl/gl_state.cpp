// FixedFunctionState: translated from format::GraphicsState (Vulkan enum values) and applied to a context.
#include "gl_state.hpp"

#include "support/failure.hpp"

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <type_traits>

// The public header spells these values out so that it needs no GL header; they must be GL's.
static_assert(statepack::gl::enums::kZero == GL_ZERO && statepack::gl::enums::kOne == GL_ONE &&
              statepack::gl::enums::kTriangles == GL_TRIANGLES && statepack::gl::enums::kLess == GL_LESS &&
              statepack::gl::enums::kAlways == GL_ALWAYS && statepack::gl::enums::kBack == GL_BACK &&
              statepack::gl::enums::kCcw == GL_CCW && statepack::gl::enums::kFloat == GL_FLOAT &&
              statepack::gl::enums::kFill == GL_FILL && statepack::gl::enums::kKeep == GL_KEEP &&
              statepack::gl::enums::kFuncAdd == GL_FUNC_ADD);
static_assert(std::is_same_v<statepack::gl::GLenum, ::GLenum> &&
              std::is_same_v<statepack::gl::GLuint, ::GLuint> &&
              std::is_same_v<statepack::gl::GLint, ::GLint> &&
              std::is_same_v<statepack::gl::GLsizei, ::GLsizei>);

namespace statepack::gl::detail {
namespace {

// Vulkan enums in this file are contiguous from 0, so each table is indexed by the Vulkan value.
constexpr GLenum kTopology[] = {
    GL_POINTS,                    // VK_PRIMITIVE_TOPOLOGY_POINT_LIST
    GL_LINES,                     // LINE_LIST
    GL_LINE_STRIP,                // LINE_STRIP
    GL_TRIANGLES,                 // TRIANGLE_LIST
    GL_TRIANGLE_STRIP,            // TRIANGLE_STRIP
    GL_TRIANGLE_FAN,              // TRIANGLE_FAN
    GL_LINES_ADJACENCY,           // LINE_LIST_WITH_ADJACENCY
    GL_LINE_STRIP_ADJACENCY,      // LINE_STRIP_WITH_ADJACENCY
    GL_TRIANGLES_ADJACENCY,       // TRIANGLE_LIST_WITH_ADJACENCY
    GL_TRIANGLE_STRIP_ADJACENCY,  // TRIANGLE_STRIP_WITH_ADJACENCY
    GL_PATCHES,                   // PATCH_LIST
};
constexpr GLenum kPolygonMode[] = {GL_FILL, GL_LINE, GL_POINT};  // VkPolygonMode FILL, LINE, POINT
// VkCompareOp NEVER .. ALWAYS
constexpr GLenum kCompare[] = {GL_NEVER,   GL_LESS,     GL_EQUAL,  GL_LEQUAL,
                               GL_GREATER, GL_NOTEQUAL, GL_GEQUAL, GL_ALWAYS};
// VkStencilOp KEEP, ZERO, REPLACE, INCREMENT_AND_CLAMP, DECREMENT_AND_CLAMP, INVERT, INCREMENT_AND_WRAP,
// DECREMENT_AND_WRAP
constexpr GLenum kStencilOp[] = {GL_KEEP, GL_ZERO,   GL_REPLACE,   GL_INCR,
                                 GL_DECR, GL_INVERT, GL_INCR_WRAP, GL_DECR_WRAP};
// VkBlendFactor ZERO .. ONE_MINUS_SRC1_ALPHA
constexpr GLenum kBlendFactor[] = {GL_ZERO,
                                   GL_ONE,
                                   GL_SRC_COLOR,
                                   GL_ONE_MINUS_SRC_COLOR,
                                   GL_DST_COLOR,
                                   GL_ONE_MINUS_DST_COLOR,
                                   GL_SRC_ALPHA,
                                   GL_ONE_MINUS_SRC_ALPHA,
                                   GL_DST_ALPHA,
                                   GL_ONE_MINUS_DST_ALPHA,
                                   GL_CONSTANT_COLOR,
                                   GL_ONE_MINUS_CONSTANT_COLOR,
                                   GL_CONSTANT_ALPHA,
                                   GL_ONE_MINUS_CONSTANT_ALPHA,
                                   GL_SRC_ALPHA_SATURATE,
                                   GL_SRC1_COLOR,
                                   GL_ONE_MINUS_SRC1_COLOR,
                                   GL_SRC1_ALPHA,
                                   GL_ONE_MINUS_SRC1_ALPHA};
// VkBlendOp ADD, SUBTRACT, REVERSE_SUBTRACT, MIN, MAX (the advanced blend ops have no core GL form)
constexpr GLenum kBlendOp[] = {GL_FUNC_ADD, GL_FUNC_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT, GL_MIN, GL_MAX};

// The table entry for `value`, or an error naming the pipeline, the field and the value.
Result<GLenum> lookup(std::span<const GLenum> table, uint32_t value, std::string_view pipeline,
                      const std::string& field) {
  if (value < table.size()) return table[value];
  return statepack::detail::failure(ErrorCode::unsupported, "pipeline '" + std::string(pipeline) +
                                                                "': " + field + " " + std::to_string(value) +
                                                                " has no OpenGL equivalent");
}

// A VkFormat as a vertex attribute format, or nullopt for one GL cannot read from a buffer.
std::optional<VertexInput::Attribute> vertex_format(uint32_t format) {
  using Path = VertexInput::Path;
  VertexInput::Attribute a;
  // Families of consecutive VkFormat values: 8-bit (UNORM, SNORM, USCALED, SSCALED, UINT, SINT, SRGB),
  // 16-bit (the same, SFLOAT for SRGB), 32-bit (UINT, SINT, SFLOAT), 64-bit (UINT, SINT, SFLOAT); one
  // family per component count.
  auto normalized_family = [&](uint32_t first, GLint size, GLenum unsigned_type, GLenum signed_type,
                               bool has_float) -> bool {
    if (format < first || format >= first + 7) return false;
    const uint32_t variant = format - first;
    a.size = size;
    switch (variant) {
      case 0:  // UNORM
      case 1:  // SNORM
        a.type = variant == 0 ? unsigned_type : signed_type, a.normalized = true;
        return true;
      case 2:  // USCALED
      case 3:  // SSCALED
        a.type = variant == 2 ? unsigned_type : signed_type;
        return true;
      case 4:  // UINT
      case 5:  // SINT
        a.type = variant == 4 ? unsigned_type : signed_type, a.path = Path::integer;
        return true;
      default:  // 8-bit SRGB (no vertex form) or 16-bit SFLOAT
        if (!has_float) return false;
        a.type = GL_HALF_FLOAT;
        return true;
    }
  };
  for (GLint n = 1; n <= 4; ++n) {
    const uint32_t eight[] = {9, 16, 23, 37};  // R8, R8G8, R8G8B8, R8G8B8A8
    const uint32_t sixteen[] = {70, 77, 84, 91};
    if (normalized_family(eight[n - 1], n, GL_UNSIGNED_BYTE, GL_BYTE, false)) return a;
    if (normalized_family(sixteen[n - 1], n, GL_UNSIGNED_SHORT, GL_SHORT, true)) return a;
    const uint32_t thirty_two = 98 + 3 * uint32_t(n - 1), sixty_four = 110 + 3 * uint32_t(n - 1);
    if (format >= thirty_two && format < thirty_two + 3) {
      a.size = n;
      a.type = format == thirty_two ? GL_UNSIGNED_INT : format == thirty_two + 1 ? GL_INT : GL_FLOAT;
      a.path = format == thirty_two + 2 ? Path::float_ : Path::integer;
      return a;
    }
    if (format == sixty_four + 2) {  // R64..._SFLOAT (64-bit integers have no GL vertex form)
      a.size = n, a.type = GL_DOUBLE, a.path = Path::double_;
      return a;
    }
  }
  switch (format) {
    case 44:  // B8G8R8A8_UNORM
      a.size = GL_BGRA, a.type = GL_UNSIGNED_BYTE, a.normalized = true;
      return a;
    case 58:  // A2R10G10B10_UNORM_PACK32
      a.size = GL_BGRA, a.type = GL_UNSIGNED_INT_2_10_10_10_REV, a.normalized = true;
      return a;
    case 64:  // A2B10G10R10_UNORM_PACK32 .. SSCALED
    case 65:
    case 66:
    case 67:
      a.size = 4;
      a.type = format == 64 || format == 66 ? GL_UNSIGNED_INT_2_10_10_10_REV : GL_INT_2_10_10_10_REV;
      a.normalized = format <= 65;
      return a;
    case 122:  // B10G11R11_UFLOAT_PACK32
      a.size = 3, a.type = GL_UNSIGNED_INT_10F_11F_11F_REV;
      return a;
    default:
      return std::nullopt;
  }
}

}  // namespace

Result<VertexInput> translate_vertex_input(const format::GraphicsState& g, std::string_view pipeline) {
  VertexInput input;
  for (const auto& b : g.vertex_bindings) {
    if (b.input_rate > 1)
      return statepack::detail::failure(ErrorCode::unsupported,
                                        "pipeline '" + std::string(pipeline) + "': vertex binding " +
                                            std::to_string(b.binding) + " has unknown input rate " +
                                            std::to_string(b.input_rate));
    input.bindings.push_back({b.binding, GLsizei(b.stride), b.input_rate == 1 ? 1u : 0u});
  }
  for (const auto& v : g.vertex_attributes) {
    auto a = vertex_format(v.format);
    if (!a)
      return statepack::detail::failure(
          ErrorCode::unsupported, "pipeline '" + std::string(pipeline) + "': vertex attribute at location " +
                                      std::to_string(v.location) + " has VkFormat " +
                                      std::to_string(v.format) +
                                      ", which OpenGL cannot read from a vertex buffer");
    a->location = v.location, a->binding = v.binding, a->offset = v.offset;
    input.attributes.push_back(*a);
  }
  return input;
}

GLenum shader_type(uint32_t vk_stage) {
  switch (vk_stage) {
    case 0x01:  // VK_SHADER_STAGE_VERTEX_BIT
      return GL_VERTEX_SHADER;
    case 0x02:  // TESSELLATION_CONTROL
      return GL_TESS_CONTROL_SHADER;
    case 0x04:  // TESSELLATION_EVALUATION
      return GL_TESS_EVALUATION_SHADER;
    case 0x08:  // GEOMETRY
      return GL_GEOMETRY_SHADER;
    case 0x10:  // FRAGMENT
      return GL_FRAGMENT_SHADER;
    case 0x20:  // COMPUTE
      return GL_COMPUTE_SHADER;
    default:
      return 0;
  }
}

Result<FixedFunctionState> translate_state(const format::GraphicsState& g, std::string_view pipeline,
                                           const Extensions& extensions) {
  FixedFunctionState s;
  const std::string name(pipeline);
  auto fail = [&](std::string what) {
    return statepack::detail::failure(ErrorCode::unsupported, "pipeline '" + name + "': " + std::move(what));
  };
  // Each lookup either sets its field or returns the error from here.
#define STATEPACK_MAP(target, table, value, field)        \
  do {                                                    \
    auto mapped_ = lookup(table, value, pipeline, field); \
    if (!mapped_) return mapped_.error();                 \
    target = *mapped_;                                    \
  } while (false)

  STATEPACK_MAP(s.primitive_mode, kTopology, g.topology, "primitive topology");
  if (s.primitive_mode == GL_PATCHES) {
    if (g.patch_control_points == 0) return fail("a patch list without control points");
    s.patch_vertices = GLint(g.patch_control_points);
  }

  switch (g.cull_mode) {
    case 0:  // VK_CULL_MODE_NONE
      s.cull_enable = false;
      break;
    case 1:
      s.cull_enable = true, s.cull_face = GL_FRONT;
      break;
    case 2:
      s.cull_enable = true, s.cull_face = GL_BACK;
      break;
    case 3:
      s.cull_enable = true, s.cull_face = GL_FRONT_AND_BACK;
      break;
    default:
      return fail("cull mode " + std::to_string(g.cull_mode) + " has no OpenGL equivalent");
  }
  // Same vertices, opposite winding (window y up in GL, down in Vulkan): see gl_dearchiver.hpp.
  switch (g.front_face) {
    case 0:  // VK_FRONT_FACE_COUNTER_CLOCKWISE
      s.front_face = GL_CW;
      break;
    case 1:  // VK_FRONT_FACE_CLOCKWISE
      s.front_face = GL_CCW;
      break;
    default:
      return fail("front face " + std::to_string(g.front_face) + " has no OpenGL equivalent");
  }
  STATEPACK_MAP(s.polygon_mode, kPolygonMode, g.polygon_mode, "polygon mode");
  s.depth_clamp = g.depth_clamp != 0;
  s.depth_bias_constant = g.depth_bias;
  s.depth_bias_slope = g.depth_bias_slope;
  s.depth_bias_clamp = g.depth_bias_clamp;
  s.depth_bias_enable = g.depth_bias != 0 || g.depth_bias_slope != 0;
  if (!std::isfinite(g.depth_bias) || !std::isfinite(g.depth_bias_slope) ||
      !std::isfinite(g.depth_bias_clamp))
    return fail("depth bias values are not finite");
  if (s.depth_bias_enable && g.depth_bias_clamp != 0 && !extensions.polygon_offset_clamp)
    return fail("depth bias clamp " + std::to_string(g.depth_bias_clamp) +
                " needs OpenGL 4.6 or GL_ARB_polygon_offset_clamp, which this context lacks");

  s.depth_test = g.depth_test != 0;
  s.depth_write = s.depth_test && g.depth_write != 0;  // Vulkan writes depth only when it tests
  STATEPACK_MAP(s.depth_func, kCompare, g.depth_compare, "depth compare op");
  s.stencil_test = g.stencil_test != 0;
  s.stencil_read_mask = g.stencil_read_mask;
  s.stencil_write_mask = g.stencil_write_mask;
  for (auto [face, out, label] :
       {std::tuple{&g.front, &s.stencil_front, "front"}, std::tuple{&g.back, &s.stencil_back, "back"}}) {
    const std::string prefix = std::string(label) + " stencil ";
    STATEPACK_MAP(out->fail_op, kStencilOp, face->fail_op, prefix + "fail op");
    STATEPACK_MAP(out->pass_op, kStencilOp, face->pass_op, prefix + "pass op");
    STATEPACK_MAP(out->depth_fail_op, kStencilOp, face->depth_fail_op, prefix + "depth-fail op");
    STATEPACK_MAP(out->func, kCompare, face->compare_op, prefix + "compare op");
  }

  s.samples = g.samples;
  s.sample_mask = g.sample_mask;
  s.alpha_to_coverage = g.alpha_to_coverage != 0;

  if (g.color_count > kMaxColorTargets)
    return fail(std::to_string(g.color_count) + " render targets (at most " +
                std::to_string(kMaxColorTargets) + ")");
  s.color_count = g.color_count;
  for (uint32_t i = 0; i < g.color_count; ++i) {
    const format::BlendAttachment& b = g.blend[i];
    BlendTarget& t = s.blend[i];
    const std::string prefix = "render target " + std::to_string(i) + " ";
    t.enable = b.enable != 0;
    STATEPACK_MAP(t.src_color, kBlendFactor, b.src_color, prefix + "source color blend factor");
    STATEPACK_MAP(t.dst_color, kBlendFactor, b.dst_color, prefix + "destination color blend factor");
    STATEPACK_MAP(t.color_op, kBlendOp, b.color_op, prefix + "color blend op");
    STATEPACK_MAP(t.src_alpha, kBlendFactor, b.src_alpha, prefix + "source alpha blend factor");
    STATEPACK_MAP(t.dst_alpha, kBlendFactor, b.dst_alpha, prefix + "destination alpha blend factor");
    STATEPACK_MAP(t.alpha_op, kBlendOp, b.alpha_op, prefix + "alpha blend op");
    if (b.write_mask > 0xF)
      return fail(prefix + "color write mask " + std::to_string(b.write_mask) + " has unknown bits");
    for (uint32_t c = 0; c < 4; ++c) t.write_mask[c] = (b.write_mask >> c) & 1u;  // R, G, B, A bits
  }
#undef STATEPACK_MAP
  return s;
}

}  // namespace statepack::gl::detail

namespace statepack::gl {

namespace {
void enable(GLenum cap, bool on) {
  if (on)
    glEnable(cap);
  else
    glDisable(cap);
}
}  // namespace

void VertexInput::configure(GLuint vertex_array) const {
  for (const Attribute& a : attributes) {
    glEnableVertexArrayAttrib(vertex_array, a.location);
    switch (a.path) {
      case Path::float_:
        glVertexArrayAttribFormat(vertex_array, a.location, a.size, a.type, a.normalized ? GL_TRUE : GL_FALSE,
                                  a.offset);
        break;
      case Path::integer:
        glVertexArrayAttribIFormat(vertex_array, a.location, a.size, a.type, a.offset);
        break;
      case Path::double_:
        glVertexArrayAttribLFormat(vertex_array, a.location, a.size, a.type, a.offset);
        break;
    }
    glVertexArrayAttribBinding(vertex_array, a.location, a.binding);
  }
  for (const BufferBinding& b : bindings) glVertexArrayBindingDivisor(vertex_array, b.binding, b.divisor);
}

void FixedFunctionState::apply(ClipY clip_y) const {
  // Vulkan's depth range and a lower-left origin (the rows land as on Vulkan: see gl_dearchiver.hpp); an
  // upper-left one lands them as a Vulkan viewport of negative height does. GL decides a polygon's facing
  // with the origin's y, so the facing Vulkan computes in framebuffer rows is the archive's inverted
  // (front_face) with the lower-left origin and the archive's own with the upper-left one.
  const bool up = clip_y == ClipY::up;
  glClipControl(up ? GL_UPPER_LEFT : GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_FRAMEBUFFER_SRGB);
  if (primitive_mode == GL_PATCHES && patch_vertices > 0)
    glPatchParameteri(GL_PATCH_VERTICES, patch_vertices);

  enable(GL_CULL_FACE, cull_enable);
  glCullFace(cull_face);
  glFrontFace(up ? (front_face == GL_CW ? GL_CCW : GL_CW) : front_face);
  glPolygonMode(GL_FRONT_AND_BACK, polygon_mode);
  enable(GL_DEPTH_CLAMP, depth_clamp);
  enable(GL_POLYGON_OFFSET_FILL, depth_bias_enable);
  enable(GL_POLYGON_OFFSET_LINE, depth_bias_enable);
  enable(GL_POLYGON_OFFSET_POINT, depth_bias_enable);
  if (depth_bias_enable) {
    // glPolygonOffset(factor, units): the slope factor scales the depth slope, units the smallest step,
    // as Vulkan's depthBiasSlopeFactor and depthBiasConstantFactor.
    if (depth_bias_clamp != 0)
      glPolygonOffsetClamp(depth_bias_slope, depth_bias_constant, depth_bias_clamp);
    else
      glPolygonOffset(depth_bias_slope, depth_bias_constant);
  }

  enable(GL_DEPTH_TEST, depth_test);
  glDepthMask(depth_write ? GL_TRUE : GL_FALSE);
  glDepthFunc(depth_func);
  enable(GL_STENCIL_TEST, stencil_test);
  glStencilFuncSeparate(GL_FRONT, stencil_front.func, stencil_reference, stencil_read_mask);
  glStencilFuncSeparate(GL_BACK, stencil_back.func, stencil_reference, stencil_read_mask);
  glStencilOpSeparate(GL_FRONT, stencil_front.fail_op, stencil_front.depth_fail_op, stencil_front.pass_op);
  glStencilOpSeparate(GL_BACK, stencil_back.fail_op, stencil_back.depth_fail_op, stencil_back.pass_op);
  glStencilMaskSeparate(GL_FRONT_AND_BACK, stencil_write_mask);

  enable(GL_SAMPLE_MASK, sample_mask != 0xFFFFFFFFu);
  glSampleMaski(0, sample_mask);
  enable(GL_SAMPLE_ALPHA_TO_COVERAGE, alpha_to_coverage);

  glBlendColor(blend_color[0], blend_color[1], blend_color[2], blend_color[3]);
  for (uint32_t i = 0; i < color_count && i < kMaxColorTargets; ++i) {
    const BlendTarget& t = blend[i];
    if (t.enable)
      glEnablei(GL_BLEND, i);
    else
      glDisablei(GL_BLEND, i);
    glBlendFuncSeparatei(i, t.src_color, t.dst_color, t.src_alpha, t.dst_alpha);
    glBlendEquationSeparatei(i, t.color_op, t.alpha_op);
    glColorMaski(i, t.write_mask[0], t.write_mask[1], t.write_mask[2], t.write_mask[3]);
  }
}

}  // namespace statepack::gl
