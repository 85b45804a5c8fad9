// Diligent's shaders as Diligent compiles them, on both backends (tests/data/diligent_style): HLSL written
// against the engine's definitions and macros, a row-vector matrix uploaded row by row with
// PACK_MATRIX_ROW_MAJOR, vertex inputs named ATTRIBn and declared out of order, the same inputs matched
// through InputLayout's HLSLSemantic, a module another compiler made (BYTECODE), and inline constants
// pushed with vkCmdPushConstants. Each image is compared with what the matrix, the inputs and
// Diligent's conventions must give (computed here), the OpenGL image with the Vulkan one, and every
// definition's value with what its name means.
#include <array>
#include <cmath>
#include <cstring>
#include <functional>

#include "gl_test_fixture.hpp"

namespace statepack::testing {
namespace {

constexpr uint32_t kSize = 32;
using Pixels = std::vector<uint8_t>;

// transform.vsh's constants: a row-vector matrix (clip = position * M) as rows, then a scale. Its
// translation row is (-1, -1, 0) and its w column 2, so clip = (2x - 1, 2y - 1, z, 2) before the scale.
struct TransformConstants {
  float rows[4][4] = {{2, 0, 0, 0}, {0, 2, 0, 0}, {0, 0, 1, 0}, {-1, -1, 0, 2}};
  float scale[4] = {1.5f, 1.0f, 0.0f, 0.0f};
};
// Per vertex: position and depth (buffer slot 0); per instance: a colour (slot 1). The triangle's
// corners in the order that is clockwise on screen once clip-space y points up (front-facing with
// Diligent's FrontCounterClockwise false, so BACK culling keeps it).
constexpr float kVertices[3][3] = {{0.0f, 0.0f, 0.5f}, {0.0f, 0.9f, 0.5f}, {0.6f, 0.0f, 0.5f}};
constexpr float kInstanceColor[4] = {0.25f, 0.75f, 0.0f, 0.0f};

// The image the transform must give, row 0 at the top (clip y = +1, Diligent's convention): inside
// the triangle (r, g) from the instance colour, b the row's texture v, a = w / 4 = 0.5; outside 0.
// Pixels within one pixel of an edge are not checked (-1).
std::vector<int> expected_transform() {
  const TransformConstants c;
  std::array<std::array<float, 2>, 3> ndc{};
  for (int v = 0; v < 3; ++v) {
    const float p[4] = {kVertices[v][0] * c.scale[0], kVertices[v][1] * c.scale[1], kVertices[v][2], 1};
    float clip[4] = {};
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) clip[col] += p[row] * c.rows[row][col];
    ndc[v] = {clip[0] / clip[3], clip[1] / clip[3]};
  }
  auto pixel_of = [](std::array<float, 2> n) {  // pixel coordinates, y down from the top row
    return std::array<float, 2>{(n[0] + 1) * 0.5f * kSize, (1 - n[1]) * 0.5f * kSize};
  };
  std::array<std::array<float, 2>, 3> px{pixel_of(ndc[0]), pixel_of(ndc[1]), pixel_of(ndc[2])};
  std::vector<int> out(size_t(kSize) * kSize * 4, 0);
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
      bool inside = true, near_edge = false;
      for (int e = 0; e < 3; ++e) {
        const auto& a = px[size_t(e)];
        const auto& b = px[size_t((e + 1) % 3)];
        const float ex = b[0] - a[0], ey = b[1] - a[1];
        const float distance = (ex * (cy - a[1]) - ey * (cx - a[0])) / std::hypot(ex, ey);
        if (std::fabs(distance) < 1.0f) near_edge = true;
        inside = inside && distance > 0;  // clockwise on screen (y down): the interior is on the right
      }
      int* p = &out[(size_t(y) * kSize + x) * 4];
      if (near_edge) {
        p[0] = p[1] = p[2] = p[3] = -1;
      } else if (inside) {
        p[0] = int(std::lround(kInstanceColor[0] * 255));
        p[1] = int(std::lround(kInstanceColor[1] * 255));
        p[2] = int(std::lround((float(y) + 0.5f) / kSize * 255));
        p[3] = 128;
      }
    }
  return out;
}

// Every checked byte within 1 of the expected one; at least `min_inside` pixels drawn.
void expect_image(const Pixels& pixels, const std::vector<int>& expected, const std::string& what) {
  ASSERT_EQ(pixels.size(), expected.size()) << what;
  size_t inside = 0;
  for (size_t i = 0; i < pixels.size(); ++i) {
    if (expected[i] < 0) continue;
    const size_t pixel = i / 4;
    ASSERT_LE(std::abs(int(pixels[i]) - expected[i]), 1)
        << what << ": pixel (" << pixel % kSize << ", " << pixel / kSize << ") channel " << i % 4;
    if (i % 4 == 3 && expected[i] > 0) ++inside;
  }
  EXPECT_GT(inside, 40u) << what << ": the triangle covers too few checked pixels to prove anything";
}

// inline_tint.psh's constants: tint, brightness, the channel set to the brightness (24 bytes).
struct TintConstants {
  float tint[4] = {0.1f, 0.2f, 0.3f, 0.4f};
  float brightness = 0.9f;
  uint32_t channel = 2;
};

class DiligentStyle : public GlTest {
 protected:
  Dearchiver vulkan_dearchiver() {
    auto dearchiver = Dearchiver::create(vk_->device_context());
    EXPECT_TRUE(dearchiver) << dearchiver.error().message;
    auto added = dearchiver->add_archive(load(STATEPACK_DILIGENT_STYLE_ARCHIVE));
    EXPECT_TRUE(added) << added.error().message;
    return std::move(dearchiver.value());
  }
  gl::Dearchiver gl_dearchiver() { return make_gl_dearchiver(load(STATEPACK_DILIGENT_STYLE_ARCHIVE)); }

  // A host buffer holding `bytes`.
  std::unique_ptr<bootstrap::HostBuffer> buffer(const void* bytes, size_t size, VkBufferUsageFlags usage) {
    auto b = bootstrap::create_host_buffer(*vk_, size, usage);
    EXPECT_TRUE(b);
    if (!b) return nullptr;
    std::memcpy((*b)->mapped, bytes, size);
    return std::move(*b);
  }

  // The transform drawn on Vulkan as Diligent's Vulkan backend draws: a viewport of negative height.
  Pixels draw_transform_vulkan(const char* pipeline) {
    Dearchiver dearchiver = vulkan_dearchiver();
    auto pso = dearchiver.unpack_graphics(pipeline, [](PatchableState& s) {
      s.color_count = 1;
      s.color_formats[0] = VK_FORMAT_R8G8B8A8_UNORM;
    });
    EXPECT_TRUE(pso) << pso.error().message;
    if (!pso) return {};
    const TransformConstants constants;
    auto ubo = buffer(&constants, sizeof constants, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
    auto vertices = buffer(kVertices, sizeof kVertices, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    auto instance = buffer(kInstanceColor, sizeof kInstanceColor, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    const BindingInfo* constants_binding = (*pso)->find_binding("Constants");
    EXPECT_NE(constants_binding, nullptr);
    if (!ubo || !vertices || !instance || !constants_binding) return {};
    EXPECT_EQ(constants_binding->type, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
    UniformSet set(*vk_, (*pso)->set_layouts.at(constants_binding->set), constants_binding->binding,
                   ubo->buffer);
    return render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, kSize, kSize, [&](VkCommandBuffer cmd) {
      const VkViewport flipped{0, float(kSize), float(kSize), -float(kSize), 0, 1};
      vkCmdSetViewport(cmd, 0, 1, &flipped);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*pso)->layout, constants_binding->set, 1,
                              &set.set, 0, nullptr);
      const VkBuffer buffers[2] = {vertices->buffer, instance->buffer};
      const VkDeviceSize offsets[2] = {0, 0};
      vkCmdBindVertexBuffers(cmd, 0, 2, buffers, offsets);
    });
  }

  // The same on OpenGL, with clip-space y up (FixedFunctionState::ClipY::up, the flipped viewport's
  // equal), read back in the same row order.
  static Pixels draw_transform_gl(gl::Dearchiver& dearchiver, const char* pipeline) {
    auto program = dearchiver.unpack_graphics(pipeline);
    EXPECT_TRUE(program) << program.error().message;
    if (!program) return {};
    const TransformConstants constants;
    GLuint buffers[3] = {};
    glCreateBuffers(3, buffers);
    glNamedBufferStorage(buffers[0], sizeof constants, &constants, 0);
    glNamedBufferStorage(buffers[1], sizeof kVertices, kVertices, 0);
    glNamedBufferStorage(buffers[2], sizeof kInstanceColor, kInstanceColor, 0);
    const gl::Binding* ubo = (*program)->find_binding("Constants");
    EXPECT_NE(ubo, nullptr);
    if (!ubo) return {};
    GLuint vertex_array = 0;
    glCreateVertexArrays(1, &vertex_array);
    (*program)->vertex_input.configure(vertex_array);
    for (const auto& b : (*program)->vertex_input.bindings)
      glVertexArrayVertexBuffer(vertex_array, b.binding, buffers[1 + b.binding], 0, b.stride);
    Pixels pixels = draw_gl(**program, vertex_array,
                            [&] { glBindBufferBase(GL_UNIFORM_BUFFER, ubo->binding, buffers[0]); });
    glDeleteVertexArrays(1, &vertex_array);
    glDeleteBuffers(3, buffers);
    return pixels;
  }

  // Draws 3 vertices (1 instance) of `program` into a new RGBA8 texture with clip-space y up; its bytes.
  static Pixels draw_gl(const gl::Program& program, GLuint vertex_array, const std::function<void()>& bind) {
    GLuint texture = 0, framebuffer = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, GL_RGBA8, kSize, kSize);
    glCreateFramebuffers(1, &framebuffer);
    glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, texture, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, kSize, kSize);
    glDisable(GL_SCISSOR_TEST);
    const GLfloat clear[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, clear);
    glUseProgram(program.program);
    glBindVertexArray(vertex_array);
    program.state.apply(gl::FixedFunctionState::ClipY::up);
    bind();
    glDrawArraysInstanced(program.state.primitive_mode, 0, 3, 1);
    Pixels pixels(size_t(kSize) * kSize * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(pixels.size()), pixels.data());
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteTextures(1, &texture);
    return pixels;
  }

  static GLuint gl_buffer(const void* data, size_t size) {
    GLuint b = 0;
    glCreateBuffers(1, &b);
    glNamedBufferStorage(b, GLsizeiptr(size), data, GL_DYNAMIC_STORAGE_BIT);
    return b;
  }
  static GLuint gl_binding_of(const gl::Program& program, const char* name, gl::Binding::Kind kind) {
    const gl::Binding* b = program.find_binding(name);
    EXPECT_NE(b, nullptr) << name;
    if (!b) return 0;
    EXPECT_EQ(b->kind, kind) << name;
    return b->binding;
  }

  // A descriptor pool with one set binding one uniform buffer.
  struct UniformSet {
    VkDevice device = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
    UniformSet(bootstrap::VulkanContext& vk, VkDescriptorSetLayout layout, uint32_t binding, VkBuffer buffer)
        : device(vk.device) {
      const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1};
      VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
      pool_info.maxSets = 1;
      pool_info.poolSizeCount = 1;
      pool_info.pPoolSizes = &size;
      EXPECT_EQ(vkCreateDescriptorPool(device, &pool_info, nullptr, &pool), VK_SUCCESS);
      VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
      alloc.descriptorPool = pool;
      alloc.descriptorSetCount = 1;
      alloc.pSetLayouts = &layout;
      EXPECT_EQ(vkAllocateDescriptorSets(device, &alloc, &set), VK_SUCCESS);
      const VkDescriptorBufferInfo info{buffer, 0, VK_WHOLE_SIZE};
      VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
      write.dstSet = set;
      write.dstBinding = binding;
      write.descriptorCount = 1;
      write.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
      write.pBufferInfo = &info;
      vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
    }
    ~UniformSet() {
      if (pool) vkDestroyDescriptorPool(device, pool, nullptr);
    }
  };
};

TEST_F(DiligentStyle, RowMajorMatrixAttribInputsAndDefinitionsDrawWhatTheyMean) {
  const std::vector<int> expected = expected_transform();
  expect_image(draw_transform_vulkan("Transform PSO"), expected, "Vulkan, Transform PSO");
}

TEST_F(DiligentStyle, InputsMatchedByHlslSemanticDrawTheSame) {
  expect_image(draw_transform_vulkan("Transform By Semantic PSO"), expected_transform(),
               "Vulkan, Transform By Semantic PSO");
}

TEST_F(DiligentStyle, AnotherCompilersModuleIsPlacedAndDrawsTheSame) {
  expect_image(draw_transform_vulkan("Transform Bytecode PSO"), expected_transform(),
               "Vulkan, Transform Bytecode PSO");
}

TEST_F(DiligentStyle, OpenGlDrawsTheSamePixelsWithClipYUp) {
  gl::Dearchiver dearchiver = gl_dearchiver();
  for (const char* pipeline : {"Transform PSO", "Transform By Semantic PSO", "Transform Bytecode PSO"}) {
    const Pixels gl_pixels = draw_transform_gl(dearchiver, pipeline);
    expect_image(gl_pixels, expected_transform(), std::string("OpenGL, ") + pipeline);
    EXPECT_LE(max_difference(gl_pixels, draw_transform_vulkan(pipeline)), 1) << pipeline;
  }
}

TEST_F(DiligentStyle, InlineConstantsArePushedAndReadBack) {
  Dearchiver dearchiver = vulkan_dearchiver();
  const TintConstants constants;
  const uint8_t want[4] = {26, 51, 230, 102};  // (0.1, 0.2, 0.9, 0.4): the tint, channel 2 set to 0.9
  for (const char* name : {"Inline Tint PSO", "Inline Tint Implicit PSO"}) {
    SCOPED_TRACE(name);
    auto pso = dearchiver.unpack_graphics(name, [](PatchableState& s) {
      s.color_count = 1;
      s.color_formats[0] = VK_FORMAT_R8G8B8A8_UNORM;
    });
    ASSERT_TRUE(pso) << pso.error().message;
    // The cbuffer is the pipeline's push constants: its bytes, in the pixel shader.
    EXPECT_EQ((*pso)->push_constant_size, sizeof constants);
    EXPECT_EQ((*pso)->push_constant_stages, VkShaderStageFlags(VK_SHADER_STAGE_FRAGMENT_BIT));
    EXPECT_EQ((*pso)->find_binding("DrawConstants") != nullptr, std::string(name) == "Inline Tint PSO")
        << "the signature keeps its (unused) descriptor, as Diligent's does; the implicit layout has none";
    const Pixels pixels =
        render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, kSize, kSize, [&](VkCommandBuffer cmd) {
          vkCmdPushConstants(cmd, (*pso)->layout, (*pso)->push_constant_stages, 0, sizeof constants,
                             &constants);
        });
    ASSERT_EQ(pixels.size(), size_t(kSize) * kSize * 4);
    for (size_t i = 0; i < pixels.size(); ++i)
      ASSERT_LE(std::abs(int(pixels[i]) - int(want[i % 4])), 1) << "byte " << i;
  }
  // OpenGL has no push constants: the same bytes are the uniform block of that name.
  gl::Dearchiver gl = gl_dearchiver();
  for (const char* name : {"Inline Tint PSO", "Inline Tint Implicit PSO"}) {
    SCOPED_TRACE(name);
    auto program = gl.unpack_graphics(name);
    ASSERT_TRUE(program) << program.error().message;
    const gl::Binding* block = (*program)->find_binding("DrawConstants");
    ASSERT_NE(block, nullptr);
    EXPECT_EQ(block->kind, gl::Binding::Kind::uniform_buffer);
    const GLuint ubo = gl_buffer(&constants, sizeof constants);
    GLuint vertex_array = 0;
    glCreateVertexArrays(1, &vertex_array);
    const Pixels pixels =
        draw_gl(**program, vertex_array, [&] { glBindBufferBase(GL_UNIFORM_BUFFER, block->binding, ubo); });
    glDeleteVertexArrays(1, &vertex_array);
    glDeleteBuffers(1, &ubo);
    for (size_t i = 0; i < pixels.size(); ++i)
      ASSERT_LE(std::abs(int(pixels[i]) - int(want[i % 4])), 1) << "byte " << i;
  }
}

// Each name of the environment, evaluated by a compute shader on both backends, against its meaning.
TEST_F(DiligentStyle, EveryDefinitionMeansWhatItsNameSays) {
  const std::vector<float> want = {
      0.25f,  0.375f,        // NormalizedDeviceXYToTexUV(-0.5, 0.25): u = 0.5 + x / 2, v = 0.5 - y / 2
      -0.5f,  -0.5f,         // TexUVToNormalizedDeviceXY(0.25, 0.75): x = 2u - 1, y = 1 - 2v
      0.375f, 0.625f, 0.0f,  // depth and normalized z are one number on Vulkan; NDC_MIN_Z
      0.5f,   -0.5f,  1.0f,  // F3NDC_XYZ_TO_UVD_SCALE
      1,      1,      0,    0, 1,
      0,      1,      0,    1,  // Less LessEqual Greater GreaterEqual Equal NotEqual Not And Or
      9.0f,                     // BoolToFloat(true, false, false, true) as bits 1 + 8
      2.0f,                     // BoolToFloat(true) + (false, true).y + (true, true, false).z
      7.0f,   13.0f,            // MATRIX_ELEMENT(m, 1, 2), (m, 3, 0) of rows (1 2 3 4), (5 6 7 8), ...
      2.0f,   2.0f,             // MatrixFromRows: rows, whichever side the vector multiplies
      1.0f};                    // COMPUTE_SHADER, GLSLANG, HLSL, VULKAN defined; no other stage's
  const auto vulkan = [&] {
    Dearchiver dearchiver = vulkan_dearchiver();
    auto pso = dearchiver.unpack_compute("Definitions PSO");
    EXPECT_TRUE(pso) << pso.error().message;
    std::vector<float> out(want.size() + 4, -100.0f);
    if (!pso) return out;
    const BindingInfo* values = (*pso)->find_binding("g_Values");
    EXPECT_NE(values, nullptr);
    auto storage = buffer(out.data(), out.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (!values || !storage) return out;
    auto set = bootstrap::bind_storage_buffer(*vk_, (*pso)->set_layouts.at(values->set), values->binding,
                                              storage->buffer);
    EXPECT_TRUE(set) << set.error().message;
    if (!set) return out;
    auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->pipeline);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->layout, values->set, 1,
                              &(*set)->set, 0, nullptr);
      vkCmdDispatch(cmd, 1, 1, 1);
    });
    EXPECT_TRUE(done) << done.error().message;
    std::memcpy(out.data(), storage->mapped, out.size() * 4);
    return out;
  }();
  const auto opengl = [&] {
    gl::Dearchiver dearchiver = gl_dearchiver();
    auto program = dearchiver.unpack_compute("Definitions PSO");
    EXPECT_TRUE(program) << program.error().message;
    std::vector<float> out(want.size() + 4, -100.0f);
    if (!program) return out;
    const GLuint storage = gl_buffer(out.data(), out.size() * 4);
    glUseProgram((*program)->program);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER,
                     gl_binding_of(**program, "g_Values", gl::Binding::Kind::storage_buffer), storage);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(storage, 0, GLsizeiptr(out.size() * 4), out.data());
    glUseProgram(0);
    glDeleteBuffers(1, &storage);
    return out;
  }();
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_FLOAT_EQ(vulkan[i], want[i]) << "Vulkan, value " << i;
    EXPECT_FLOAT_EQ(opengl[i], want[i]) << "OpenGL, value " << i;
  }
  EXPECT_EQ(vulkan[want.size()], -100.0f) << "the shader wrote past its values";
}

}  // namespace
}  // namespace statepack::testing
