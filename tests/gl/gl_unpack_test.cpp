// The OpenGL backend on Mesa's llvmpipe (EGL surfaceless, OpenGL 4.5 + GL_ARB_gl_spirv): programs from
// the archive's GL block dispatch and draw, and their results are compared with the same pipelines of
// the same archive (packed with --vulkan --opengl) run on Vulkan (lavapipe) in the same test. Any GL debug
// error message fails the test that caused it, as any validation message does on the Vulkan side.
#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "common/forged_archive.hpp"
#include "common/vulkan_test_fixture.hpp"
#include "format/archive_format.hpp"
#include "gl/gl_state.hpp"
#include "gl_test_fixture.hpp"
#include "runtime/archive_access.hpp"
#include "statepack/bootstrap/gl_context.hpp"
#include "statepack/gl_dearchiver.hpp"

namespace statepack::testing {
namespace {

TEST_F(GlTest, ContextIsLlvmpipeWithSpirv) {
  EXPECT_NE(gl_->renderer.find("llvmpipe"), std::string::npos) << gl_->renderer;
  EXPECT_GE(epoxy_gl_version(), 45);
  EXPECT_TRUE(epoxy_has_gl_extension("GL_ARB_gl_spirv"));
}

TEST_F(GlTest, ComputeFillsBufferAsOnVulkan) {
  gl::Dearchiver dearchiver = make_gl_dearchiver();
  auto program = dearchiver.unpack_compute("Fill Buffer PSO");
  ASSERT_TRUE(program) << program.error().message;
  EXPECT_TRUE((*program)->compute);
  EXPECT_NE((*program)->program, 0u);

  constexpr uint32_t kCount = 1000;  // not a multiple of the 64-wide workgroup: the bound check matters
  std::vector<uint32_t> on_gl = fill_buffer_gl(**program, kCount, 7, 5);
  std::vector<uint32_t> on_vulkan = fill_buffer_vulkan(kCount, 7, 5);
  ASSERT_EQ(on_gl.size(), size_t(kCount + 24));
  ASSERT_EQ(on_vulkan.size(), on_gl.size());
  for (size_t i = 0; i < on_gl.size(); ++i) ASSERT_EQ(on_gl[i], on_vulkan[i]) << "at index " << i;
  EXPECT_EQ(on_gl[kCount - 1], (kCount - 1) * 7 + 5);
  EXPECT_EQ(on_gl[kCount], 0xABABABABu) << "the shader wrote past params.count";
}

TEST_F(GlTest, GradientDrawsAsOnVulkan) {
  gl::Dearchiver dearchiver = make_gl_dearchiver();
  auto program = dearchiver.unpack_graphics("Gradient PSO");
  ASSERT_TRUE(program) << program.error().message;
  const gl::FixedFunctionState& state = (*program)->state;
  EXPECT_FALSE((*program)->compute);
  EXPECT_EQ(state.primitive_mode, GLenum(GL_TRIANGLES));
  EXPECT_FALSE(state.cull_enable);  // the notation's CullMode NONE
  EXPECT_FALSE(state.depth_test);   // DepthEnable false
  EXPECT_EQ(state.color_count, 1u);

  constexpr uint32_t kSize = 64;
  std::vector<uint8_t> on_gl = render_gl(**program, state, kSize, kSize);

  Dearchiver vulkan = make_vulkan_dearchiver();
  auto pso = vulkan.unpack_graphics("Gradient PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  std::vector<uint8_t> on_vulkan = render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, kSize, kSize);
  ASSERT_EQ(on_gl.size(), on_vulkan.size());

  // glReadPixels returns the bottom row first, Vulkan's copy the top row first; but the same clip-space
  // y = -1 is GL's bottom (window y up) and Vulkan's top (framebuffer y down), so both buffers start with
  // the row at clip y = -1 and match byte for byte without flipping. The flipped comparison must fail:
  // it proves the gradient runs along y, so the row order really is checked.
  std::vector<uint8_t> flipped(on_gl.size());
  for (uint32_t y = 0; y < kSize; ++y)
    std::memcpy(&flipped[size_t(y) * kSize * 4], &on_gl[size_t(kSize - 1 - y) * kSize * 4], kSize * 4);
  const int difference = max_difference(on_gl, on_vulkan);
  std::printf("Gradient PSO, %ux%u RGBA8: max difference GL vs Vulkan = %d (rows flipped: %d)\n", kSize,
              kSize, difference, max_difference(flipped, on_vulkan));
  EXPECT_GT(max_difference(flipped, on_vulkan), 100);
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x)
      for (uint32_t c = 0; c < 4; ++c) {
        const size_t i = (size_t(y) * kSize + x) * 4 + c;
        ASSERT_NEAR(on_gl[i], on_vulkan[i], 1) << "pixel (" << x << ", " << y << ") channel " << c;
      }
}

// The archive's front face is Vulkan's (clockwise, Diligent's default); glFrontFace gets the opposite
// winding so that GL culls what Vulkan culls: the full-screen triangle is front-facing on both.
TEST_F(GlTest, CullingMatchesVulkan) {
  auto original = load(STATEPACK_GL_ARCHIVE);
  format::Contents contents = detail::ArchiveAccess::contents(original);
  for (VkCullModeFlags cull : {VK_CULL_MODE_FRONT_BIT, VK_CULL_MODE_BACK_BIT}) {
    for (auto& p : contents.gl_pipelines)
      if (p.name == "Gradient PSO") p.graphics.cull_mode = cull;
    ArchiveBytes bytes = encode_aligned(contents);
    auto archive = Archive::from_memory(bytes.bytes());
    ASSERT_TRUE(archive) << archive.error().message;
    gl::Dearchiver dearchiver = make_gl_dearchiver(std::move(*archive));
    auto program = dearchiver.unpack_graphics("Gradient PSO");
    ASSERT_TRUE(program) << program.error().message;
    EXPECT_TRUE((*program)->state.cull_enable);
    std::vector<uint8_t> on_gl = render_gl(**program, (*program)->state, 16, 16);

    Dearchiver vulkan = make_vulkan_dearchiver();
    auto pso =
        vulkan.unpack_graphics("Gradient PSO", [&](PatchableState& s) { s.rasterizer.cull_mode = cull; });
    ASSERT_TRUE(pso) << pso.error().message;
    std::vector<uint8_t> on_vulkan = render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, 16, 16);
    const bool front = cull == VK_CULL_MODE_FRONT_BIT;
    EXPECT_EQ(all_zero(on_vulkan), front) << "Vulkan, culling " << (front ? "front" : "back") << " faces";
    EXPECT_EQ(all_zero(on_gl), front) << "OpenGL, culling " << (front ? "front" : "back") << " faces";
    EXPECT_LE(max_difference(on_gl, on_vulkan), 1);
  }
}

TEST_F(GlTest, UnpackingTwiceReturnsTheSameProgram) {
  gl::Dearchiver dearchiver = make_gl_dearchiver();
  auto first = dearchiver.unpack_compute("Fill Buffer PSO");
  auto second = dearchiver.unpack_compute("Fill Buffer PSO");
  ASSERT_TRUE(first && second);
  EXPECT_EQ(*first, *second);
  auto gradient1 = dearchiver.unpack_graphics("Gradient PSO");
  auto gradient2 = dearchiver.unpack_graphics("Gradient PSO");
  ASSERT_TRUE(gradient1 && gradient2);
  EXPECT_EQ(*gradient1, *gradient2);
  EXPECT_NE(*first, *gradient1);
  auto names = dearchiver.program_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "Fill Buffer PSO"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "Gradient PSO"), names.end());
}

TEST_F(GlTest, BindingsByName) {
  gl::Dearchiver dearchiver = make_gl_dearchiver();
  auto program = dearchiver.unpack_compute("Fill Buffer PSO");
  ASSERT_TRUE(program) << program.error().message;
  const gl::Binding* values = (*program)->find_binding("Values");
  ASSERT_NE(values, nullptr);
  EXPECT_EQ(values->kind, gl::Binding::Kind::storage_buffer);
  EXPECT_EQ(values->stages, uint32_t(VK_SHADER_STAGE_COMPUTE_BIT));
  EXPECT_EQ(values->count, 1u);
  // Vulkan's push constants become a uniform block in GL.
  const gl::Binding* params = (*program)->find_binding("Params");
  ASSERT_NE(params, nullptr);
  EXPECT_EQ(params->kind, gl::Binding::Kind::uniform_buffer);
  EXPECT_EQ((*program)->find_binding("Nothing"), nullptr);
}

TEST_F(GlTest, UnknownNameIsAnErrorWithSuggestion) {
  gl::Dearchiver dearchiver = make_gl_dearchiver();
  auto program = dearchiver.unpack_graphics("Gradient PS0");
  ASSERT_FALSE(program);
  EXPECT_EQ(program.error().code, ErrorCode::not_found);
  EXPECT_NE(program.error().message.find("'Gradient PS0'"), std::string::npos) << program.error().message;
  EXPECT_NE(program.error().message.find("did you mean 'Gradient PSO'"), std::string::npos)
      << program.error().message;
}

TEST_F(GlTest, WrongPipelineTypeIsAnError) {
  gl::Dearchiver dearchiver = make_gl_dearchiver();
  auto program = dearchiver.unpack_compute("Gradient PSO");
  ASSERT_FALSE(program);
  EXPECT_EQ(program.error().code, ErrorCode::wrong_type);
  EXPECT_EQ(program.error().message,
            "pipeline 'Gradient PSO' is a graphics pipeline, not a compute pipeline");
  // Also once the other kind is cached under that name.
  ASSERT_TRUE(dearchiver.unpack_graphics("Gradient PSO"));
  auto again = dearchiver.unpack_compute("Gradient PSO");
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error().code, ErrorCode::wrong_type);
}

TEST_F(GlTest, VulkanOnlyArchiveIsMissingBackend) {
  auto dearchiver = gl::Dearchiver::create();
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  auto added = dearchiver->add_archive(load(STATEPACK_TEST_ARCHIVE));  // packed without --opengl
  ASSERT_FALSE(added);
  EXPECT_EQ(added.error().code, ErrorCode::missing_backend);
  EXPECT_NE(added.error().message.find("--opengl"), std::string::npos) << added.error().message;
}

// The Vulkan runtime loads an archive without reading its OpenGL block; the GL dearchiver checks that
// block where it is used: a binding table missing the shader's storage buffer is refused at add_archive.
TEST_F(GlTest, ABrokenOpenGlBlockIsRefusedWhereItIsUsed) {
  Archive good = load(STATEPACK_GL_ARCHIVE);
  format::Contents broken = detail::ArchiveAccess::contents(good);
  for (auto& p : broken.gl_pipelines)
    if (p.name == "Fill Buffer PSO") p.bindings.clear();
  ForgedBytes bytes(format::encode(broken));
  auto archive = Archive::from_memory(bytes.span());
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = gl::Dearchiver::create();
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  auto added = dearchiver->add_archive(std::move(*archive));
  ASSERT_FALSE(added);
  EXPECT_EQ(added.error().code, ErrorCode::corrupt);
  EXPECT_NE(added.error().message.find("gl::Dearchiver::add_archive: corrupt archive: OpenGL pipeline 'Fill "
                                       "Buffer PSO', shader 'Fill Buffer CS': the resource at binding 0 has "
                                       "no binding of its kind"),
            std::string::npos)
      << added.error().message;
}

TEST_F(GlTest, CreateWithoutCurrentContextIsUnsupported) {
  ASSERT_TRUE(gl_->release_current());
  auto dearchiver = gl::Dearchiver::create();
  ASSERT_TRUE(gl_->make_current());
  ASSERT_FALSE(dearchiver);
  EXPECT_EQ(dearchiver.error().code, ErrorCode::unsupported);
  EXPECT_EQ(dearchiver.error().message,
            "gl::Dearchiver::create: no OpenGL context is current on the calling thread");
}

// The loader refuses unknown enum values, so the translation's own checks are tested directly.
TEST(GlStateTranslation, UnmappableValuesAreErrorsNamingThePipeline) {
  format::GraphicsState state;
  state.color_count = 1;
  state.blend[0].color_op = 1000148000;  // VK_BLEND_OP_ZERO_EXT: advanced blending, no core GL form
  auto translated = gl::detail::translate_state(state, "Blend PSO", {});
  ASSERT_FALSE(translated);
  EXPECT_EQ(translated.error().code, ErrorCode::unsupported);
  EXPECT_EQ(translated.error().message,
            "pipeline 'Blend PSO': render target 0 color blend op 1000148000 has no OpenGL equivalent");

  format::GraphicsState clamped;
  clamped.depth_bias = 2;
  clamped.depth_bias_clamp = 0.5f;
  auto no_clamp = gl::detail::translate_state(clamped, "Bias PSO", {});
  ASSERT_FALSE(no_clamp);
  EXPECT_EQ(no_clamp.error().code, ErrorCode::unsupported);
  EXPECT_NE(no_clamp.error().message.find("GL_ARB_polygon_offset_clamp"), std::string::npos);
  EXPECT_TRUE(gl::detail::translate_state(clamped, "Bias PSO", {.polygon_offset_clamp = true}));

  format::GraphicsState topology;
  topology.topology = 11;
  EXPECT_FALSE(gl::detail::translate_state(topology, "Topology PSO", {}));
}

TEST(GlStateTranslation, VulkanValuesBecomeGlEnums) {
  format::GraphicsState g;
  g.topology = 4;       // TRIANGLE_STRIP
  g.cull_mode = 1;      // FRONT
  g.front_face = 0;     // COUNTER_CLOCKWISE: GL's CW (y flipped)
  g.polygon_mode = 1;   // LINE
  g.depth_compare = 6;  // GREATER_OR_EQUAL
  g.stencil_test = 1;
  g.stencil_read_mask = 0x0F;
  g.stencil_write_mask = 0xF0;
  g.front = {1, 2, 3, 4};  // fail ZERO, pass REPLACE, depth fail INCREMENT_AND_CLAMP, compare GREATER
  g.back = {7, 6, 5, 0};   // DECREMENT_AND_WRAP, INCREMENT_AND_WRAP, INVERT, NEVER
  g.depth_bias = 1.5f;
  g.depth_bias_slope = 2;
  g.color_count = 2;
  g.blend[1] = {1, 6, 7, 4, 1, 0, 3, 0x5};  // SRC_ALPHA, ONE_MINUS_SRC_ALPHA, MAX; ONE, ZERO, MIN; R and B
  auto t = gl::detail::translate_state(g, "Mapped PSO", {});
  ASSERT_TRUE(t) << t.error().message;
  EXPECT_EQ(t->primitive_mode, GLenum(GL_TRIANGLE_STRIP));
  EXPECT_TRUE(t->cull_enable);
  EXPECT_EQ(t->cull_face, GLenum(GL_FRONT));
  EXPECT_EQ(t->front_face, GLenum(GL_CW));
  EXPECT_EQ(t->polygon_mode, GLenum(GL_LINE));
  EXPECT_EQ(t->depth_func, GLenum(GL_GEQUAL));
  EXPECT_TRUE(t->stencil_test);
  EXPECT_EQ(t->stencil_read_mask, 0x0Fu);
  EXPECT_EQ(t->stencil_write_mask, 0xF0u);
  EXPECT_EQ(t->stencil_front.fail_op, GLenum(GL_ZERO));
  EXPECT_EQ(t->stencil_front.pass_op, GLenum(GL_REPLACE));
  EXPECT_EQ(t->stencil_front.depth_fail_op, GLenum(GL_INCR));
  EXPECT_EQ(t->stencil_front.func, GLenum(GL_GREATER));
  EXPECT_EQ(t->stencil_back.fail_op, GLenum(GL_DECR_WRAP));
  EXPECT_EQ(t->stencil_back.pass_op, GLenum(GL_INCR_WRAP));
  EXPECT_EQ(t->stencil_back.depth_fail_op, GLenum(GL_INVERT));
  EXPECT_EQ(t->stencil_back.func, GLenum(GL_NEVER));
  EXPECT_TRUE(t->depth_bias_enable);
  EXPECT_EQ(t->depth_bias_constant, 1.5f);
  EXPECT_EQ(t->depth_bias_slope, 2.0f);
  EXPECT_EQ(t->color_count, 2u);
  const gl::BlendTarget& b = t->blend[1];
  EXPECT_TRUE(b.enable);
  EXPECT_EQ(b.src_color, GLenum(GL_SRC_ALPHA));
  EXPECT_EQ(b.dst_color, GLenum(GL_ONE_MINUS_SRC_ALPHA));
  EXPECT_EQ(b.color_op, GLenum(GL_MAX));
  EXPECT_EQ(b.src_alpha, GLenum(GL_ONE));
  EXPECT_EQ(b.dst_alpha, GLenum(GL_ZERO));
  EXPECT_EQ(b.alpha_op, GLenum(GL_MIN));
  EXPECT_EQ(b.write_mask, (std::array<bool, 4>{true, false, true, false}));
  EXPECT_FALSE(t->blend[0].enable);
}

TEST(GlStateTranslation, VertexInputBecomesVertexArrayFormat) {
  format::GraphicsState g;
  g.vertex_bindings = {{0, 28, VK_VERTEX_INPUT_RATE_VERTEX}, {1, 16, VK_VERTEX_INPUT_RATE_INSTANCE}};
  g.vertex_attributes = {
      {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}, {1, 0, VK_FORMAT_R8G8B8A8_UNORM, 12},
      {2, 0, VK_FORMAT_R16G16_SFLOAT, 16},   {3, 0, VK_FORMAT_R32_UINT, 20},
      {4, 0, VK_FORMAT_B8G8R8A8_UNORM, 24},  {5, 1, VK_FORMAT_R16G16B16A16_SNORM, 0},
      {6, 1, VK_FORMAT_R8G8_SINT, 8},        {7, 1, VK_FORMAT_A2B10G10R10_UNORM_PACK32, 12}};
  auto input = gl::detail::translate_vertex_input(g, "Mesh PSO");
  ASSERT_TRUE(input) << input.error().message;
  ASSERT_EQ(input->bindings.size(), 2u);
  EXPECT_EQ(input->bindings[0].stride, 28);
  EXPECT_EQ(input->bindings[0].divisor, 0u);
  EXPECT_EQ(input->bindings[1].divisor, 1u);
  ASSERT_EQ(input->attributes.size(), 8u);
  using Path = gl::VertexInput::Path;
  struct Want {
    GLint size;
    GLenum type;
    bool normalized;
    Path path;
  };
  const Want want[] = {{3, GL_FLOAT, false, Path::float_},
                       {4, GL_UNSIGNED_BYTE, true, Path::float_},
                       {2, GL_HALF_FLOAT, false, Path::float_},
                       {1, GL_UNSIGNED_INT, false, Path::integer},
                       {GL_BGRA, GL_UNSIGNED_BYTE, true, Path::float_},
                       {4, GL_SHORT, true, Path::float_},
                       {2, GL_BYTE, false, Path::integer},
                       {4, GL_UNSIGNED_INT_2_10_10_10_REV, true, Path::float_}};
  for (size_t i = 0; i < 8; ++i) {
    const auto& a = input->attributes[i];
    EXPECT_EQ(a.location, g.vertex_attributes[i].location);
    EXPECT_EQ(a.binding, g.vertex_attributes[i].binding);
    EXPECT_EQ(a.offset, g.vertex_attributes[i].offset);
    EXPECT_EQ(a.size, want[i].size) << "attribute " << i;
    EXPECT_EQ(a.type, want[i].type) << "attribute " << i;
    EXPECT_EQ(a.normalized, want[i].normalized) << "attribute " << i;
    EXPECT_EQ(a.path, want[i].path) << "attribute " << i;
  }

  g.vertex_attributes = {{3, 0, VK_FORMAT_R8G8B8A8_SRGB, 0}};
  auto srgb = gl::detail::translate_vertex_input(g, "Mesh PSO");
  ASSERT_FALSE(srgb);
  EXPECT_EQ(srgb.error().code, ErrorCode::unsupported);
  EXPECT_EQ(
      srgb.error().message,
      "pipeline 'Mesh PSO': vertex attribute at location 3 has VkFormat 43, which OpenGL cannot read from a "
      "vertex buffer");
}

// A VAO configured from a translated vertex input raises no GL error.
TEST_F(GlTest, VertexInputConfiguresAVertexArray) {
  format::GraphicsState g;
  g.vertex_bindings = {{0, 32, VK_VERTEX_INPUT_RATE_VERTEX}, {1, 8, VK_VERTEX_INPUT_RATE_INSTANCE}};
  g.vertex_attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                         {1, 0, VK_FORMAT_R32G32_UINT, 12},
                         {2, 0, VK_FORMAT_R64_SFLOAT, 20},
                         {3, 1, VK_FORMAT_B8G8R8A8_UNORM, 0}};
  auto input = gl::detail::translate_vertex_input(g, "Mesh PSO");
  ASSERT_TRUE(input) << input.error().message;
  GLuint vertex_array = 0;
  glCreateVertexArrays(1, &vertex_array);
  input->configure(vertex_array);
  GLint divisor = -1, type = 0, integer = -1;
  glGetVertexArrayIndexediv(vertex_array, 3, GL_VERTEX_ATTRIB_ARRAY_DIVISOR, &divisor);
  glGetVertexArrayIndexediv(vertex_array, 1, GL_VERTEX_ATTRIB_ARRAY_TYPE, &type);
  glGetVertexArrayIndexediv(vertex_array, 1, GL_VERTEX_ATTRIB_ARRAY_INTEGER, &integer);
  glDeleteVertexArrays(1, &vertex_array);
  EXPECT_EQ(divisor, 1);
  EXPECT_EQ(GLenum(type), GLenum(GL_UNSIGNED_INT));
  EXPECT_EQ(integer, GL_TRUE);
}

// The fixture's debug callback really records errors (so the other tests' silence means something).
TEST_F(GlTest, DebugCallbackRecordsErrors) {
  glEnable(0xFFFF);  // GL_INVALID_ENUM
  auto messages = gl_->error_messages();
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_NE(messages[0].find("llvmpipe"), std::string::npos) << messages[0];
  gl_->clear_messages();
}

// A specialization constant the shader does not have never reaches glSpecializeShader (where the driver
// would raise GL_INVALID_VALUE): add_archive checks GL constants against the SPIR-V as loading does
// Vulkan's.
TEST_F(GlTest, UndeclaredSpecializationConstantIsRefusedAtLoad) {
  auto original = load(STATEPACK_GL_ARCHIVE);
  format::Contents contents = detail::ArchiveAccess::contents(original);
  for (auto& p : contents.gl_pipelines)
    if (p.name == "Fill Buffer PSO")
      p.constants.push_back({"missing", VK_SHADER_STAGE_COMPUTE_BIT, 77, 4, 1});
  ArchiveBytes bytes = encode_aligned(contents);
  auto loaded = Archive::from_memory(bytes.bytes());
  ASSERT_TRUE(loaded) << loaded.error().message;  // the Vulkan part is sound
  auto dearchiver = gl::Dearchiver::create();
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  auto archive = dearchiver->add_archive(std::move(*loaded));
  ASSERT_FALSE(archive);
  EXPECT_EQ(archive.error().code, ErrorCode::corrupt);
  EXPECT_NE(archive.error().message.find("OpenGL pipeline 'Fill Buffer PSO': specialization constant "
                                         "'missing' (id 77) is not declared by shader "
                                         "'Fill Buffer CS'"),
            std::string::npos)
      << archive.error().message;
  EXPECT_TRUE(gl_->error_messages().empty());
}

}  // namespace
}  // namespace statepack::testing
