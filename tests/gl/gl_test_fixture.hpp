// The OpenGL test fixture: a headless llvmpipe context (EGL surfaceless, OpenGL 4.5 + GL_ARB_gl_spirv)
// beside the Vulkan device, with helpers that run the same pipeline on both backends. Any GL debug
// error fails the test that caused it, as any validation message does on the Vulkan side.
#pragma once

#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "common/vulkan_test_fixture.hpp"
#include "format/archive_format.hpp"
#include "runtime/archive_access.hpp"
#include "statepack/bootstrap/gl_context.hpp"
#include "statepack/gl_dearchiver.hpp"

namespace statepack::testing {

// Archive bytes kept in 4-byte aligned memory, for Archive::from_memory.
struct ArchiveBytes {
  std::vector<uint32_t> words;
  size_t size = 0;
  std::span<const uint8_t> bytes() const { return {reinterpret_cast<const uint8_t*>(words.data()), size}; }
};

inline ArchiveBytes encode_aligned(const format::Contents& contents) {
  std::vector<uint8_t> bytes = format::encode(contents);
  ArchiveBytes out;
  out.words.resize((bytes.size() + 3) / 4);
  std::memcpy(out.words.data(), bytes.data(), bytes.size());
  out.size = bytes.size();
  return out;
}

class GlTest : public VulkanTest {
 protected:
  void SetUp() override {
    bootstrap::GlContextOptions options;
    options.require_llvmpipe = true;
    auto created = bootstrap::GlContext::create(options);
    ASSERT_TRUE(created) << created.error().message;
    gl_ = std::move(created.value());
    VulkanTest::SetUp();
  }

  void TearDown() override {
    VulkanTest::TearDown();
    if (!gl_) return;
    for (const auto& message : gl_->error_messages()) ADD_FAILURE() << message;
  }

  static Archive load(const char* path) {
    auto archive = Archive::from_file(path);
    EXPECT_TRUE(archive) << archive.error().message;
    return std::move(archive.value());
  }

  // A GL dearchiver with the GL slice archive loaded.
  gl::Dearchiver make_gl_dearchiver(Archive archive) {
    auto dearchiver = gl::Dearchiver::create();
    EXPECT_TRUE(dearchiver) << dearchiver.error().message;
    auto added = dearchiver->add_archive(std::move(archive));
    EXPECT_TRUE(added) << added.error().message;
    return std::move(dearchiver.value());
  }
  gl::Dearchiver make_gl_dearchiver() { return make_gl_dearchiver(load(STATEPACK_GL_ARCHIVE)); }

  // A Vulkan dearchiver with the same archive (packed for both backends).
  Dearchiver make_vulkan_dearchiver() {
    auto dearchiver = Dearchiver::create(vk_->device_context());
    EXPECT_TRUE(dearchiver) << dearchiver.error().message;
    auto added = dearchiver->add_archive(load(STATEPACK_GL_ARCHIVE));
    EXPECT_TRUE(added) << added.error().message;
    return std::move(dearchiver.value());
  }

  // Draws a graphics program (a full-screen triangle, 3 vertices) into a width x height RGBA8 texture
  // and returns its rows as glReadPixels gives them: window row 0 (the bottom one) first.
  static std::vector<uint8_t> render_gl(const gl::Program& program, const gl::FixedFunctionState& state,
                                        GLsizei width, GLsizei height) {
    GLuint texture = 0, framebuffer = 0, vertex_array = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, GL_RGBA8, width, height);
    glCreateFramebuffers(1, &framebuffer);
    glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, texture, 0);
    EXPECT_EQ(glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    glCreateVertexArrays(1, &vertex_array);  // core profile: a draw needs one, even without attributes

    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width, height);
    glDisable(GL_SCISSOR_TEST);
    const GLfloat clear[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, clear);
    glUseProgram(program.program);
    glBindVertexArray(vertex_array);
    state.apply();
    glDrawArrays(state.primitive_mode, 0, 3);

    std::vector<uint8_t> pixels(size_t(width) * height * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());

    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteVertexArrays(1, &vertex_array);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteTextures(1, &texture);
    return pixels;
  }

  // Runs Fill Buffer PSO on GL: `count` values into a buffer of count + 24 words pre-filled with 0xAB.
  static std::vector<uint32_t> fill_buffer_gl(const gl::Program& program, uint32_t count, uint32_t multiplier,
                                              uint32_t offset) {
    const gl::Binding* values = program.find_binding("Values");
    const gl::Binding* params = program.find_binding("Params");
    EXPECT_NE(values, nullptr);
    EXPECT_NE(params, nullptr);
    if (!values || !params) return {};
    EXPECT_EQ(values->kind, gl::Binding::Kind::storage_buffer);
    EXPECT_EQ(params->kind, gl::Binding::Kind::uniform_buffer);
    std::vector<uint32_t> initial(count + 24, 0xABABABABu);
    GLuint buffers[2] = {};
    glCreateBuffers(2, buffers);
    glNamedBufferStorage(buffers[0], GLsizeiptr(initial.size() * 4), initial.data(), 0);
    const uint32_t uniforms[4] = {count, multiplier, offset, 0};  // std140: 12 bytes, padded to 16
    glNamedBufferStorage(buffers[1], sizeof uniforms, uniforms, 0);

    glUseProgram(program.program);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, values->binding, buffers[0]);
    glBindBufferBase(GL_UNIFORM_BUFFER, params->binding, buffers[1]);
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<uint32_t> out(initial.size());
    glGetNamedBufferSubData(buffers[0], 0, GLsizeiptr(out.size() * 4), out.data());

    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, values->binding, 0);
    glBindBufferBase(GL_UNIFORM_BUFFER, params->binding, 0);
    glUseProgram(0);
    glDeleteBuffers(2, buffers);
    return out;
  }

  // The same on Vulkan (as tests/runtime/slice_test.cpp dispatches it, with push constants).
  std::vector<uint32_t> fill_buffer_vulkan(uint32_t count, uint32_t multiplier, uint32_t offset) {
    Dearchiver dearchiver = make_vulkan_dearchiver();
    auto pso = dearchiver.unpack_compute("Fill Buffer PSO");
    EXPECT_TRUE(pso) << pso.error().message;
    if (!pso) return {};
    const BindingInfo* values = (*pso)->find_binding("Values");
    EXPECT_NE(values, nullptr);
    if (!values) return {};
    auto buffer = bootstrap::create_host_buffer(*vk_, (count + 24) * sizeof(uint32_t),
                                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    EXPECT_TRUE(buffer);
    if (!buffer) return {};
    std::memset((*buffer)->mapped, 0xAB, (*buffer)->size);
    auto set = bootstrap::bind_storage_buffer(*vk_, (*pso)->set_layouts.at(values->set), values->binding,
                                              (*buffer)->buffer);
    EXPECT_TRUE(set) << set.error().message;
    if (!set) return {};
    const uint32_t params[3] = {count, multiplier, offset};
    auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->pipeline);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->layout, values->set, 1,
                              &(*set)->set, 0, nullptr);
      vkCmdPushConstants(cmd, (*pso)->layout, (*pso)->push_constant_stages, 0, sizeof params, params);
      vkCmdDispatch(cmd, (count + 63) / 64, 1, 1);
    });
    EXPECT_TRUE(done) << done.error().message;
    const auto* mapped = static_cast<const uint32_t*>((*buffer)->mapped);
    return std::vector<uint32_t>(mapped, mapped + count + 24);
  }

  // Largest per-channel difference between two RGBA8 images of the same size.
  static int max_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    int worst = 0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
      worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
    return worst;
  }

  static bool all_zero(const std::vector<uint8_t>& pixels) {
    return std::all_of(pixels.begin(), pixels.end(), [](uint8_t v) { return v == 0; });
  }

  std::unique_ptr<bootstrap::GlContext> gl_;
};

}  // namespace statepack::testing
