// Diligent's Tutorial25 pattern, end to end, on both backends (tests/data/tutorial_like): HLSL with
// #includes and the `_sampler` suffix convention, a 4-target G-buffer pass, a pass that samples it, a
// resolve pass with push constants, and no render targets in the notation (the application sets them
// at run time). It is packed with Diligent's own command line, unpacked on lavapipe with the tutorial's
// patches and linked on llvmpipe's OpenGL, and every pass must give the same pixels on both.
// Also: an HLSL compute shader, and ordinary Vulkan GLSL (gl_VertexIndex, a push-constant block, a
// separate texture and sampler) on OpenGL, each compared with Vulkan.
#include <cmath>
#include <filesystem>
#include <functional>
#include <span>

#include "common/run_command.hpp"
#include "format/archive_file.hpp"
#include "gl_test_fixture.hpp"

namespace statepack::testing {
namespace {

namespace fs = std::filesystem;

constexpr uint32_t kWidth = 32, kHeight = 24;

// One render target, as Vulkan and OpenGL spell it; `bytes`: per pixel.
struct Target {
  VkFormat vk;
  GLenum gl_internal, gl_format, gl_type;
  uint32_t bytes;
};
constexpr Target kRgba8{VK_FORMAT_R8G8B8A8_UNORM, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, 4};
constexpr Target kGBuffer[4] = {
    kRgba8,
    kRgba8,
    // Packed alike on both: R in bits 0-10, G in 11-21, B in 22-31.
    {VK_FORMAT_B10G11R11_UFLOAT_PACK32, GL_R11F_G11F_B10F, GL_RGB, GL_UNSIGNED_INT_10F_11F_11F_REV, 4},
    {VK_FORMAT_R32_SFLOAT, GL_R32F, GL_RED, GL_FLOAT, 4}};
constexpr Target kRadiance{VK_FORMAT_R32G32B32A32_SFLOAT, GL_RGBA32F, GL_RGBA, GL_FLOAT, 16};

// G-buffer constants (tests/data/tutorial_like/assets/g_buffer.psh): 1 / size, phase, emission.
struct GBufferConstants {
  float params[4] = {1.0f / kWidth, 1.0f / kHeight, 0.3f, 2.0f};
};
struct ResolveConstants {  // resolve.psh's push constants
  float scale = 0.5f, bias = 0.125f, pad[2] = {0, 0};
};

using Pixels = std::vector<uint8_t>;

// The tutorial's patch: render targets are the application's.
void set_targets(PatchableState& s, std::span<const Target> targets) {
  s.color_count = uint32_t(targets.size());
  for (size_t i = 0; i < targets.size(); ++i) s.color_formats[i] = targets[i].vk;
}

// A descriptor pool with one set of `layout`, written with buffers and sampled images.
struct VulkanSet {
  VkDevice device = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  ~VulkanSet() {
    if (pool) vkDestroyDescriptorPool(device, pool, nullptr);
  }
};

class TutorialLike : public GlTest {
 protected:
  struct Write {
    uint32_t binding;
    VkDescriptorType type;
    VkBuffer buffer = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
  };

  std::unique_ptr<VulkanSet> make_set(VkDescriptorSetLayout layout, const std::vector<Write>& writes) {
    auto out = std::make_unique<VulkanSet>();
    out->device = vk_->device;
    const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 4},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 4},
                                          {VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 8},
                                          {VK_DESCRIPTOR_TYPE_SAMPLER, 8}};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 4;
    pool_info.pPoolSizes = sizes;
    EXPECT_EQ(vkCreateDescriptorPool(vk_->device, &pool_info, nullptr, &out->pool), VK_SUCCESS);
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = out->pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &layout;
    EXPECT_EQ(vkAllocateDescriptorSets(vk_->device, &alloc, &out->set), VK_SUCCESS);
    std::vector<VkDescriptorBufferInfo> buffers(writes.size());
    std::vector<VkDescriptorImageInfo> images(writes.size());
    std::vector<VkWriteDescriptorSet> vk_writes;
    for (size_t i = 0; i < writes.size(); ++i) {
      VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
      w.dstSet = out->set;
      w.dstBinding = writes[i].binding;
      w.descriptorCount = 1;
      w.descriptorType = writes[i].type;
      buffers[i] = {writes[i].buffer, 0, VK_WHOLE_SIZE};
      images[i] = {VK_NULL_HANDLE, writes[i].view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
      if (writes[i].buffer)
        w.pBufferInfo = &buffers[i];
      else
        w.pImageInfo = &images[i];
      vk_writes.push_back(w);
    }
    vkUpdateDescriptorSets(vk_->device, uint32_t(vk_writes.size()), vk_writes.data(), 0, nullptr);
    return out;
  }

  // Vulkan: a full-screen triangle into new images of `targets` (left SHADER_READ_ONLY for the next
  // pass), with their bytes read back.
  using VulkanPass = RenderedTargets;
  VulkanPass draw_vulkan(const UnpackedPipeline& pso, std::span<const Target> targets,
                         const std::function<void(VkCommandBuffer)>& bind) {
    std::vector<TargetFormat> formats;
    for (const Target& t : targets) formats.push_back({t.vk, t.bytes});
    return render_targets(pso, formats, kWidth, kHeight, bind);
  }

  // OpenGL: the same into new textures (kept for the next pass), read back in the same row order (see
  // gl_dearchiver.hpp: GL's first row and Vulkan's first row are the same clip-space row).
  struct GlPass {
    std::vector<GLuint> textures;
    std::vector<Pixels> pixels;
    ~GlPass() {
      if (!textures.empty()) glDeleteTextures(GLsizei(textures.size()), textures.data());
    }
  };
  static std::unique_ptr<GlPass> draw_gl(const gl::Program& program, std::span<const Target> targets,
                                         const std::function<void()>& bind) {
    auto pass = std::make_unique<GlPass>();
    pass->textures.resize(targets.size());
    glCreateTextures(GL_TEXTURE_2D, GLsizei(targets.size()), pass->textures.data());
    GLuint framebuffer = 0, vertex_array = 0;
    glCreateFramebuffers(1, &framebuffer);
    std::vector<GLenum> buffers;
    for (size_t i = 0; i < targets.size(); ++i) {
      glTextureStorage2D(pass->textures[i], 1, targets[i].gl_internal, kWidth, kHeight);
      glNamedFramebufferTexture(framebuffer, GLenum(GL_COLOR_ATTACHMENT0 + i), pass->textures[i], 0);
      buffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
    }
    glNamedFramebufferDrawBuffers(framebuffer, GLsizei(buffers.size()), buffers.data());
    EXPECT_EQ(glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    glCreateVertexArrays(1, &vertex_array);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, kWidth, kHeight);
    glDisable(GL_SCISSOR_TEST);
    glUseProgram(program.program);
    glBindVertexArray(vertex_array);
    program.state.apply();
    bind();
    glDrawArrays(program.state.primitive_mode, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteVertexArrays(1, &vertex_array);
    glDeleteFramebuffers(1, &framebuffer);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    for (size_t i = 0; i < targets.size(); ++i) {
      Pixels pixels(size_t(kWidth) * kHeight * targets[i].bytes);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glGetTextureImage(pass->textures[i], 0, targets[i].gl_format, targets[i].gl_type,
                        GLsizei(pixels.size()), pixels.data());
      pass->pixels.push_back(std::move(pixels));
    }
    return pass;
  }

  // A GL sampler like the notation's immutable ones (POINT, CLAMP): OpenGL has no immutable samplers.
  struct GlSampler {
    GLuint sampler = 0;
    GlSampler() {
      glCreateSamplers(1, &sampler);
      glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    ~GlSampler() { glDeleteSamplers(1, &sampler); }
  };

  static GLuint gl_buffer(const void* data, size_t size) {
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, GLsizeiptr(size), data, 0);
    return buffer;
  }

  static uint32_t gl_binding(const gl::Program& program, const char* name, gl::Binding::Kind kind) {
    const gl::Binding* b = program.find_binding(name);
    EXPECT_NE(b, nullptr) << program.name << ": " << name;
    if (!b) return 0;
    EXPECT_EQ(b->kind, kind) << name;
    return b->binding;
  }

  static const BindingInfo& vk_binding(const UnpackedPipeline& pso, const char* name) {
    const BindingInfo* b = pso.find_binding(name);
    EXPECT_NE(b, nullptr) << pso.name << ": " << name;
    static const BindingInfo none;
    return b ? *b : none;
  }

  // Per channel: RGBA8 within 1; floats within a relative 1e-5 (both run llvmpipe's code).
  static void expect_same(const Pixels& gl, const Pixels& vk, const Target& t, const std::string& what) {
    ASSERT_EQ(gl.size(), vk.size()) << what;
    for (size_t i = 0; i < gl.size();) {
      const size_t pixel = i / t.bytes;
      const std::string at =
          what + ": pixel (" + std::to_string(pixel % kWidth) + ", " + std::to_string(pixel / kWidth) + ")";
      if (t.gl_type == GL_FLOAT) {
        float a = 0, b = 0;
        std::memcpy(&a, &gl[i], 4);
        std::memcpy(&b, &vk[i], 4);
        ASSERT_TRUE(std::isfinite(a) && std::isfinite(b)) << at;
        ASSERT_NEAR(a, b, 1e-5f * std::max(1.0f, std::fabs(b))) << at;
        i += 4;
      } else if (t.gl_type == GL_UNSIGNED_INT_10F_11F_11F_REV) {
        uint32_t a = 0, b = 0;
        std::memcpy(&a, &gl[i], 4);
        std::memcpy(&b, &vk[i], 4);
        const int fields[3][2] = {{0, 11}, {11, 11}, {22, 10}};
        for (const auto& [shift, width] : fields)  // one step of the small float's mantissa at most
          ASSERT_LE(
              std::abs(int((a >> shift) & ((1u << width) - 1)) - int((b >> shift) & ((1u << width) - 1))), 1)
              << at;
        i += 4;
      } else {
        ASSERT_LE(std::abs(int(gl[i]) - int(vk[i])), 1) << at << " byte " << i % t.bytes;
        i += 1;
      }
    }
  }

  // Not blank and not flat: a comparison of two empty images proves nothing.
  static void expect_varied(const Pixels& rgba8, const std::string& what) {
    ASSERT_FALSE(rgba8.empty()) << what;
    const auto [lo, hi] = std::minmax_element(rgba8.begin(), rgba8.end());
    EXPECT_GT(int(*hi) - int(*lo), 100) << what;
  }

  // The tutorial's G-buffer pass (4 targets, its constants) on Vulkan, patched as the tutorial does.
  VulkanPass draw_gbuffer_vulkan(Dearchiver& dearchiver) {
    auto gbuffer =
        dearchiver.unpack_graphics("G-Buffer PSO", [](PatchableState& s) { set_targets(s, kGBuffer); });
    EXPECT_TRUE(gbuffer) << gbuffer.error().message;
    if (!gbuffer) return {};
    const GBufferConstants constants;
    auto ubo = bootstrap::create_host_buffer(*vk_, sizeof constants, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
    EXPECT_TRUE(ubo);
    if (!ubo) return {};
    std::memcpy((*ubo)->mapped, &constants, sizeof constants);
    const BindingInfo& cb = vk_binding(**gbuffer, "cbConstants");
    auto set = make_set((*gbuffer)->set_layouts.at(cb.set),
                        {{cb.binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, (*ubo)->buffer}});
    VulkanPass pass = draw_vulkan(**gbuffer, kGBuffer, [&](VkCommandBuffer cmd) {
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*gbuffer)->layout, cb.set, 1, &set->set,
                              0, nullptr);
    });
    EXPECT_EQ(pass.pixels.size(), 4u);
    return pass;
  }

  // The same on OpenGL.
  static std::unique_ptr<GlPass> draw_gbuffer_gl(gl::Dearchiver& dearchiver) {
    auto gbuffer = dearchiver.unpack_graphics("G-Buffer PSO");
    EXPECT_TRUE(gbuffer) << gbuffer.error().message;
    if (!gbuffer) return nullptr;
    EXPECT_EQ((*gbuffer)->state.color_count, 4u);  // a blend state for each target the shader writes
    const GBufferConstants constants;
    const GLuint ubo = gl_buffer(&constants, sizeof constants);
    auto pass = draw_gl(**gbuffer, kGBuffer, [&] {
      glBindBufferBase(GL_UNIFORM_BUFFER,
                       gl_binding(**gbuffer, "cbConstants", gl::Binding::Kind::uniform_buffer), ubo);
    });
    glDeleteBuffers(1, &ubo);
    return pass;
  }

  fs::path packed_archive() {
    const fs::path out = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "tutorial_like.spk";
    fs::create_directories(out.parent_path());
    // Diligent's own command line for Tutorial25, unchanged (run where RenderStates.json is).
    last_pack_ = run_command("cd '" + std::string(STATEPACK_TUTORIAL_LIKE_DIR) + "' && '" + STATEPACK_EXE +
                             "' -i RenderStates.json -r assets -s assets -o '" + out.string() +
                             "' --dx11 --dx12 --webgpu --opengl --vulkan --metal_macos --metal_ios "
                             "--print_contents");
    EXPECT_EQ(last_pack_.exit_code, 0) << last_pack_.output;
    return out;
  }

  CommandResult last_pack_;
};

TEST_F(TutorialLike, DiligentsCommandLinePacksBothBackends) {
  packed_archive();
  const std::string& out = last_pack_.output;
  for (const char* flag : {"--dx11", "--dx12", "--webgpu", "--metal_macos", "--metal_ios"}) {
    const std::string warning =
        std::string("statepack: warning: ") + flag + ": this backend cannot be produced";
    EXPECT_NE(out.find(warning), std::string::npos) << warning << "\n" << out;
    EXPECT_EQ(out.find(warning), out.rfind(warning)) << "once: " << warning;
  }
  // One note per pipeline whose targets are left to run time, no error, no other warning.
  // The note names both fixes: the notation (where a forgotten RTVFormats belongs) and the callback.
  EXPECT_NE(
      out.find("note: pipeline 'G-Buffer PSO': pixel shader 'G-Buffer PS' writes render target(s) 0, "
               "1, 2, 3, which the notation leaves to run time (0 in NumRenderTargets/RTVFormats): give "
               "them in the notation (NumRenderTargets and RTVFormats), or set them in the modify callback "
               "(PatchableState::color_count and color_formats), or unpacking fails"),
      std::string::npos)
      << out;
  EXPECT_EQ(out.find("error"), std::string::npos) << out;
  // --print_contents lists both backends, every pipeline on each.
  EXPECT_NE(out.find("backends: [\"vulkan\",\"opengl\"]"), std::string::npos) << out;
  for (const char* name : {"G-Buffer PSO", "Shade PSO", "Resolve PSO", "Scale PSO"}) {
    EXPECT_NE(out.find(std::string("\npipeline '") + name + "'"), std::string::npos) << name << "\n" << out;
    EXPECT_NE(out.find(std::string("\nOpenGL pipeline '") + name + "'"), std::string::npos) << name << "\n"
                                                                                            << out;
  }
  // Diligent's convention on OpenGL: g_Albedo + g_Albedo_sampler is one texture g_Albedo; g_Depth (read
  // with Load) is one too; the resolve's push constants are a uniform block.
  for (const char* line :
       {"  texture 0: 'g_Albedo' x1", "  texture 3: 'g_Depth' x1", "  uniform buffer 0: '$PushConstants' x1"})
    EXPECT_NE(out.find(line), std::string::npos) << line << "\n" << out;
}

TEST_F(TutorialLike, UnpackingWithoutThePatchesNamesTheMissingTargets) {
  auto archive = Archive::from_file(packed_archive());
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver && dearchiver->add_archive(std::move(*archive)));
  auto gbuffer = dearchiver->unpack_graphics("G-Buffer PSO");
  ASSERT_FALSE(gbuffer);
  EXPECT_EQ(gbuffer.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(
      gbuffer.error().message,
      "pipeline 'G-Buffer PSO': its pixel shader 'G-Buffer PS' writes render target 0, but the pipeline "
      "has 0 render target(s): the notation leaves them to run time, so set PatchableState::color_count "
      "(to at least 4) and color_formats in the modify callback, or give NumRenderTargets and RTVFormats "
      "in the notation and pack again");
  // Three targets of four is still a mistake, named at the first one missing.
  auto three = dearchiver->unpack_graphics("G-Buffer PSO",
                                           [](PatchableState& s) { set_targets(s, std::span(kGBuffer, 3)); });
  ASSERT_FALSE(three);
  EXPECT_NE(three.error().message.find("writes render target 3, but the pipeline has 3 render target(s)"),
            std::string::npos)
      << three.error().message;
}

TEST_F(TutorialLike, EveryPassDrawsTheSamePixelsOnVulkanAndOpenGl) {
  const fs::path path = packed_archive();
  auto archive = Archive::from_file(path);
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver && dearchiver->add_archive(std::move(*archive)));
  gl::Dearchiver gl_dearchiver = make_gl_dearchiver(load(path.c_str()));

  // --- Vulkan, patched as the tutorial's ModifyPipelineStateCreateInfo does.
  auto shade = dearchiver->unpack_graphics(
      "Shade PSO", [](PatchableState& s) { set_targets(s, std::span(&kRadiance, 1)); });
  ASSERT_TRUE(shade) << shade.error().message;
  auto resolve = dearchiver->unpack_graphics(
      "Resolve PSO", [](PatchableState& s) { set_targets(s, std::span(&kRgba8, 1)); });
  ASSERT_TRUE(resolve) << resolve.error().message;
  const ResolveConstants push;
  VulkanPass vk_gbuffer = draw_gbuffer_vulkan(*dearchiver);
  ASSERT_EQ(vk_gbuffer.pixels.size(), 4u);

  const char* gbuffer_names[4] = {"g_Albedo", "g_Normal", "g_Emittance", "g_Depth"};
  std::vector<Write> shade_writes;
  for (int i = 0; i < 4; ++i) {
    const BindingInfo& b = vk_binding(**shade, gbuffer_names[i]);
    EXPECT_EQ(b.set, 0u);
    shade_writes.push_back(
        {b.binding, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, VK_NULL_HANDLE, vk_gbuffer.images[size_t(i)]->view});
  }
  auto shade_set = make_set((*shade)->set_layouts.at(0), shade_writes);
  VulkanPass vk_shade = draw_vulkan(**shade, std::span(&kRadiance, 1), [&](VkCommandBuffer cmd) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*shade)->layout, 0, 1, &shade_set->set, 0,
                            nullptr);
  });
  ASSERT_EQ(vk_shade.images.size(), 1u);

  const BindingInfo& radiance = vk_binding(**resolve, "g_Radiance");
  auto resolve_set = make_set(
      (*resolve)->set_layouts.at(radiance.set),
      {{radiance.binding, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, VK_NULL_HANDLE, vk_shade.images[0]->view}});
  VulkanPass vk_resolve = draw_vulkan(**resolve, std::span(&kRgba8, 1), [&](VkCommandBuffer cmd) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*resolve)->layout, radiance.set, 1,
                            &resolve_set->set, 0, nullptr);
    vkCmdPushConstants(cmd, (*resolve)->layout, (*resolve)->push_constant_stages, 0, sizeof push, &push);
  });
  ASSERT_EQ(vk_resolve.pixels.size(), 1u);

  // --- OpenGL: the same three programs from the archive's OpenGL block.
  auto gl_shade = gl_dearchiver.unpack_graphics("Shade PSO");
  ASSERT_TRUE(gl_shade) << gl_shade.error().message;
  auto gl_resolve = gl_dearchiver.unpack_graphics("Resolve PSO");
  ASSERT_TRUE(gl_resolve) << gl_resolve.error().message;
  auto gl_gbuffer_pass = draw_gbuffer_gl(gl_dearchiver);
  ASSERT_NE(gl_gbuffer_pass, nullptr);
  GlSampler point;
  auto gl_shade_pass = draw_gl(**gl_shade, std::span(&kRadiance, 1), [&] {
    for (int i = 0; i < 4; ++i) {
      const uint32_t unit = gl_binding(**gl_shade, gbuffer_names[i], gl::Binding::Kind::texture);
      glBindTextureUnit(unit, gl_gbuffer_pass->textures[size_t(i)]);
      glBindSampler(unit, point.sampler);
    }
  });
  const GLuint gl_push = gl_buffer(&push, sizeof push);
  auto gl_resolve_pass = draw_gl(**gl_resolve, std::span(&kRgba8, 1), [&] {
    const uint32_t unit = gl_binding(**gl_resolve, "g_Radiance", gl::Binding::Kind::texture);
    glBindTextureUnit(unit, gl_shade_pass->textures[0]);
    glBindSampler(unit, point.sampler);
    glBindBufferBase(GL_UNIFORM_BUFFER,
                     gl_binding(**gl_resolve, "$PushConstants", gl::Binding::Kind::uniform_buffer), gl_push);
  });
  for (GLuint unit = 0; unit < 4; ++unit) glBindSampler(unit, 0);
  glDeleteBuffers(1, &gl_push);

  // --- The same pixels, pass by pass; and they are the tutorial's values, not two blank images.
  const char* target_names[4] = {"albedo", "normal", "emittance", "depth"};
  for (size_t i = 0; i < 4; ++i)
    expect_same(gl_gbuffer_pass->pixels[i], vk_gbuffer.pixels[i], kGBuffer[i], target_names[i]);
  expect_same(gl_shade_pass->pixels[0], vk_shade.pixels[0], kRadiance, "radiance");
  expect_same(gl_resolve_pass->pixels[0], vk_resolve.pixels[0], kRgba8, "resolved");
  expect_varied(vk_resolve.pixels[0], "resolved (Vulkan)");
  expect_varied(vk_gbuffer.pixels[0], "albedo (Vulkan)");
  // Albedo is (u, v, 1 - u, c) at the pixel centre: the first row is v = 0.5 / height on both.
  for (uint32_t y : {0u, kHeight - 1})
    for (uint32_t x : {0u, kWidth / 2, kWidth - 1}) {
      const uint8_t* p = &gl_gbuffer_pass->pixels[0][(size_t(y) * kWidth + x) * 4];
      const double u = (x + 0.5) / kWidth, v = (y + 0.5) / kHeight;
      EXPECT_NEAR(p[0], u * 255, 1) << x << ", " << y;
      EXPECT_NEAR(p[1], v * 255, 1) << x << ", " << y;
      EXPECT_NEAR(p[2], (1 - u) * 255, 1) << x << ", " << y;
      EXPECT_NEAR(p[3], 0.3 * 255, 1) << x << ", " << y;
    }
}

// The tutorial's compute shader (HLSL: a cbuffer and a RWStructuredBuffer) gives the same values.
TEST_F(TutorialLike, HlslComputeFillsTheSameValuesOnBothBackends) {
  const fs::path path = packed_archive();
  constexpr uint32_t kCount = 1000, kMultiplier = 7;
  const uint32_t uniforms[4] = {kCount, kMultiplier, 0, 0};
  std::vector<uint32_t> initial(kCount + 24, 0xABABABABu);

  auto archive = Archive::from_file(path);
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver && dearchiver->add_archive(std::move(*archive)));
  auto pso = dearchiver->unpack_compute("Scale PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  auto values = bootstrap::create_host_buffer(*vk_, initial.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  auto ubo = bootstrap::create_host_buffer(*vk_, sizeof uniforms, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  ASSERT_TRUE(values && ubo);
  std::memcpy((*values)->mapped, initial.data(), initial.size() * 4);
  std::memcpy((*ubo)->mapped, uniforms, sizeof uniforms);
  const BindingInfo& cb = vk_binding(**pso, "cbScaleConstants");
  const BindingInfo& buffer = vk_binding(**pso, "g_Values");
  ASSERT_EQ(cb.set, buffer.set);
  auto set = make_set((*pso)->set_layouts.at(cb.set),
                      {{cb.binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, (*ubo)->buffer},
                       {buffer.binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, (*values)->buffer}});
  auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->layout, cb.set, 1, &set->set, 0,
                            nullptr);
    vkCmdDispatch(cmd, (kCount + 63) / 64, 1, 1);
  });
  ASSERT_TRUE(done) << done.error().message;
  const auto* mapped = static_cast<const uint32_t*>((*values)->mapped);
  const std::vector<uint32_t> on_vulkan(mapped, mapped + initial.size());

  gl::Dearchiver gl_dearchiver = make_gl_dearchiver(load(path.c_str()));
  auto program = gl_dearchiver.unpack_compute("Scale PSO");
  ASSERT_TRUE(program) << program.error().message;
  const GLuint gl_values = gl_buffer(initial.data(), initial.size() * 4);
  const GLuint gl_ubo = gl_buffer(uniforms, sizeof uniforms);
  glUseProgram((*program)->program);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER,
                   gl_binding(**program, "g_Values", gl::Binding::Kind::storage_buffer), gl_values);
  glBindBufferBase(GL_UNIFORM_BUFFER,
                   gl_binding(**program, "cbScaleConstants", gl::Binding::Kind::uniform_buffer), gl_ubo);
  glDispatchCompute((kCount + 63) / 64, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<uint32_t> on_gl(initial.size());
  glGetNamedBufferSubData(gl_values, 0, GLsizeiptr(on_gl.size() * 4), on_gl.data());
  glUseProgram(0);
  glDeleteBuffers(1, &gl_values);
  glDeleteBuffers(1, &gl_ubo);

  for (size_t i = 0; i < on_gl.size(); ++i) ASSERT_EQ(on_gl[i], on_vulkan[i]) << "at index " << i;
  EXPECT_EQ(on_gl[kCount - 1], (kCount - 1) * kMultiplier + 3);
  EXPECT_EQ(on_gl[kCount], 0xABABABABu) << "wrote past g_Count";
}

// Ordinary Vulkan GLSL (tests/data/vulkan_glsl: gl_VertexIndex, a push-constant block, set = 1, a
// separate texture and sampler) on OpenGL: it copies the tutorial's albedo target with a tint, as on
// Vulkan.
TEST_F(TutorialLike, VulkanGlslWithPushConstantsAndSeparateSamplersDrawsAlikeOnOpenGl) {
  const fs::path tutorial = packed_archive();
  auto archive = Archive::from_file(tutorial);
  auto copy_archive = Archive::from_file(STATEPACK_VULKAN_GLSL_ARCHIVE);
  ASSERT_TRUE(archive && copy_archive);
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver && dearchiver->add_archive(std::move(*archive)) &&
              dearchiver->add_archive(std::move(*copy_archive)));
  struct Tint {
    float scale[4] = {0.5f, 1.0f, 0.25f, 1.0f};
    float bias[4] = {0.25f, 0.0f, 0.5f, 0.0f};
  } tint;

  // The source image: the tutorial's albedo, drawn on each backend.
  auto copy = dearchiver->unpack_graphics("Tinted Copy PSO");
  ASSERT_TRUE(copy) << copy.error().message;
  VulkanPass source = draw_gbuffer_vulkan(*dearchiver);
  ASSERT_EQ(source.images.size(), 4u);
  const BindingInfo& image = vk_binding(**copy, "source");
  EXPECT_EQ(image.set, 1u);
  auto copy_set =
      make_set((*copy)->set_layouts.at(1),
               {{image.binding, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, VK_NULL_HANDLE, source.images[0]->view}});
  // Set 0 holds only the immutable sampler: a set of its layout with nothing to write.
  auto sampler_set = make_set((*copy)->set_layouts.at(0), {});
  VulkanPass vk_copy = draw_vulkan(**copy, std::span(&kRgba8, 1), [&](VkCommandBuffer cmd) {
    VkDescriptorSet sets[2] = {sampler_set->set, copy_set->set};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*copy)->layout, 0, 2, sets, 0, nullptr);
    vkCmdPushConstants(cmd, (*copy)->layout, (*copy)->push_constant_stages, 0, sizeof tint, &tint);
  });

  gl::Dearchiver gl_dearchiver = make_gl_dearchiver(load(tutorial.c_str()));
  ASSERT_TRUE(gl_dearchiver.add_archive(load(STATEPACK_VULKAN_GLSL_ARCHIVE)));
  auto gl_copy = gl_dearchiver.unpack_graphics("Tinted Copy PSO");
  ASSERT_TRUE(gl_copy) << gl_copy.error().message;
  auto gl_source = draw_gbuffer_gl(gl_dearchiver);
  ASSERT_NE(gl_source, nullptr);
  GlSampler point;
  const GLuint gl_tint = gl_buffer(&tint, sizeof tint);
  auto gl_copy_pass = draw_gl(**gl_copy, std::span(&kRgba8, 1), [&] {
    const uint32_t unit = gl_binding(**gl_copy, "source", gl::Binding::Kind::texture);
    glBindTextureUnit(unit, gl_source->textures[0]);
    glBindSampler(unit, point.sampler);
    glBindBufferBase(GL_UNIFORM_BUFFER,
                     gl_binding(**gl_copy, "$PushConstants", gl::Binding::Kind::uniform_buffer), gl_tint);
  });
  glBindSampler(0, 0);
  glDeleteBuffers(1, &gl_tint);

  expect_same(gl_copy_pass->pixels[0], vk_copy.pixels[0], kRgba8, "tinted copy");
  expect_varied(vk_copy.pixels[0], "tinted copy (Vulkan)");
  // And it is the tint applied to the source: red = albedo red * 0.5 + 0.25.
  const Pixels& albedo = source.pixels[0];
  for (size_t p = 0; p < albedo.size(); p += 4 * 37)
    ASSERT_NEAR(double(vk_copy.pixels[0][p]), std::round(std::min(255.0, albedo[p] * 0.5 + 0.25 * 255)), 1.0)
        << p;
}

// Vulkan GLSL whose stages each declare their own view of the push constants and of a uniform block (a
// vertex shader the first member, a pixel shader a later one, at its offset): valid Vulkan, merged into
// one definition for OpenGL, which links one per block. The same bytes give the same pixels.
TEST_F(TutorialLike, PerStageBlockViewsDrawAlikeOnOpenGl) {
  struct Push {
    float offset[4] = {0.25f, 0.0f, 0.0f, 0.0f};
    float color[4] = {0.5f, 1.0f, 0.25f, 1.0f};
  } push;
  struct Params {
    float scale[4] = {0.5f, 0.5f, 0.0f, 0.0f};
    float tint[4] = {1.0f, 0.5f, 1.0f, 1.0f};
  } params;
  auto archive = Archive::from_file(STATEPACK_VULKAN_GLSL_ARCHIVE);
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver && dearchiver->add_archive(std::move(*archive)));
  auto pso = dearchiver->unpack_graphics("Per-Stage Blocks PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  EXPECT_EQ((*pso)->push_constant_size, sizeof push);
  auto ubo = bootstrap::create_host_buffer(*vk_, sizeof params, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  ASSERT_TRUE(ubo);
  std::memcpy((*ubo)->mapped, &params, sizeof params);
  const BindingInfo& block = vk_binding(**pso, "Params");
  auto set = make_set((*pso)->set_layouts.at(block.set),
                      {{block.binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, (*ubo)->buffer}});
  VulkanPass vk_pass = draw_vulkan(**pso, std::span(&kRgba8, 1), [&](VkCommandBuffer cmd) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*pso)->layout, block.set, 1, &set->set, 0,
                            nullptr);
    vkCmdPushConstants(cmd, (*pso)->layout, (*pso)->push_constant_stages, 0, sizeof push, &push);
  });

  gl::Dearchiver gl_dearchiver = make_gl_dearchiver(load(STATEPACK_VULKAN_GLSL_ARCHIVE));
  auto program = gl_dearchiver.unpack_graphics("Per-Stage Blocks PSO");
  ASSERT_TRUE(program) << program.error().message;
  const GLuint gl_push = gl_buffer(&push, sizeof push), gl_params = gl_buffer(&params, sizeof params);
  auto gl_pass = draw_gl(**program, std::span(&kRgba8, 1), [&] {
    glBindBufferBase(GL_UNIFORM_BUFFER,
                     gl_binding(**program, "$PushConstants", gl::Binding::Kind::uniform_buffer), gl_push);
    glBindBufferBase(GL_UNIFORM_BUFFER, gl_binding(**program, "Params", gl::Binding::Kind::uniform_buffer),
                     gl_params);
  });
  glDeleteBuffers(1, &gl_push);
  glDeleteBuffers(1, &gl_params);

  expect_same(gl_pass->pixels[0], vk_pass.pixels[0], kRgba8, "per-stage block views");
  // Inside the shifted, halved triangle: the pushed colour times the tint, (0.5, 0.5, 0.25, 1); outside 0.
  const size_t inside = (size_t(kHeight) / 2 * kWidth + kWidth / 2 + 2) * 4;
  const uint8_t want[4] = {128, 128, 64, 255};
  for (size_t c = 0; c < 4; ++c) EXPECT_NEAR(double(vk_pass.pixels[0][inside + c]), want[c], 1.0) << c;
  for (size_t c = 0; c < 4; ++c) EXPECT_EQ(vk_pass.pixels[0][c], 0) << "the corner is outside";
}

// Tessellation on OpenGL (GL 4.5 has it): the same patch, the same evaluated coordinates, the same image.
TEST_F(TutorialLike, TessellationDrawsAlikeOnOpenGl) {
  auto archive = Archive::from_file(STATEPACK_VULKAN_GLSL_ARCHIVE);
  ASSERT_TRUE(archive) << archive.error().message;
  // Format 4 (GLTS), which a version-3 reader must refuse rather than read without the patch size.
  const format::Contents contents = detail::ArchiveAccess::contents(*archive);
  EXPECT_EQ(contents.format_version, format::kGlTessellationVersion);
  {
    const std::vector<uint8_t> bytes = format::encode(contents);
    EXPECT_EQ(bytes[12], format::kGlTessellationVersion) << "oldest_readable_version";
    // Patches without a size, and a size without patches, are refused by the OpenGL block's checks
    // (format::check_opengl, which gl::Dearchiver::add_archive runs).
    auto opengl_refusal = [](const format::Contents& m) -> std::string {
      ArchiveBytes forged = encode_aligned(m);
      auto loaded = format::load_archive_with_opengl(forged.bytes(), std::nullopt, "forged");
      return loaded ? "" : loaded.error().message;
    };
    for (uint32_t points : {0u, 33u}) {
      format::Contents m = contents;
      for (auto& p : m.gl_pipelines)
        if (p.name == "Tessellated Triangle PSO") p.graphics.patch_control_points = points;
      EXPECT_NE(opengl_refusal(m).find("patch control points"), std::string::npos) << points;
    }
    format::Contents m = contents;
    for (auto& p : m.gl_pipelines)
      if (p.name == "Tessellated Triangle PSO") p.shaders.erase(p.shaders.begin() + 1);  // one stage only
    const std::string refused = opengl_refusal(m);
    EXPECT_NE(refused.find("needs both tessellation stages and a patch list topology"), std::string::npos)
        << refused;
  }
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver && dearchiver->add_archive(std::move(*archive)));
  auto pso = dearchiver->unpack_graphics("Tessellated Triangle PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  const Pixels on_vulkan = render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, kWidth, kHeight);

  gl::Dearchiver gl_dearchiver = make_gl_dearchiver(load(STATEPACK_VULKAN_GLSL_ARCHIVE));
  auto program = gl_dearchiver.unpack_graphics("Tessellated Triangle PSO");
  ASSERT_TRUE(program) << program.error().message;
  EXPECT_EQ((*program)->state.primitive_mode, GLenum(GL_PATCHES));
  EXPECT_EQ((*program)->state.patch_vertices, 3);
  const Pixels on_gl = render_gl(**program, (*program)->state, kWidth, kHeight);
  expect_same(on_gl, on_vulkan, kRgba8, "tessellated");
  expect_varied(on_vulkan, "tessellated (Vulkan)");
}

// Specialization constants survive the translation: the notation's values reach glSpecializeShader (the
// shader's defaults would give 1 and 2.0).
TEST_F(TutorialLike, TranslatedSpecializationConstantsTakeTheNotationsValues) {
  const fs::path out = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "specialization_gl.spk";
  CommandResult pack =
      run_command("cd '" + std::string(STATEPACK_CORPUS_DIR) + "/valid' && '" + STATEPACK_EXE +
                  "' pack -i specialization_and_dynamic_state.json -s ../shaders -o '" + out.string() +
                  "' --vulkan --opengl");
  ASSERT_EQ(pack.exit_code, 0) << pack.output;
  gl::Dearchiver gl_dearchiver = make_gl_dearchiver(load(out.c_str()));
  auto program = gl_dearchiver.unpack_compute("Specialized CS");
  ASSERT_TRUE(program) << program.error().message;
  const uint32_t initial[2] = {0, 0};
  const GLuint buffer = gl_buffer(initial, sizeof initial);
  glUseProgram((*program)->program);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER,
                   gl_binding(**program, "Result", gl::Binding::Kind::storage_buffer), buffer);
  glDispatchCompute(1, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  uint32_t result[2] = {};
  glGetNamedBufferSubData(buffer, 0, sizeof result, result);
  glUseProgram(0);
  glDeleteBuffers(1, &buffer);
  float scaled = 0;
  std::memcpy(&scaled, &result[1], 4);
  EXPECT_EQ(result[0], 995u);  // kNegate true, kBase 5
  EXPECT_EQ(scaled, -0.5f);    // kScale -0.25
}

// Every program of every valid corpus file, packed for both backends, links on llvmpipe with no GL
// error, and lists the bindings its Vulkan pipeline has (by name; separate samplers become part of
// their texture, push constants the $PushConstants block).
TEST_F(TutorialLike, EveryCorpusProgramLinksOnOpenGl) {
  auto archives = corpus_archives();  // tests/CMakeLists.txt: corpus_gl/*.spk for this executable
  ASSERT_GE(archives.size(), 10u);
  size_t programs = 0;
  for (const auto& path : archives) {
    SCOPED_TRACE(path);
    auto loaded = Archive::from_file(path);
    ASSERT_TRUE(loaded) << loaded.error().message;
    const format::Contents contents = detail::ArchiveAccess::contents(*loaded);
    if (contents.gl_pipelines.empty()) continue;  // a notation without pipelines
    gl::Dearchiver gl_dearchiver = make_gl_dearchiver(std::move(*loaded));
    for (const format::GlPipeline& p : contents.gl_pipelines) {
      auto program = p.kind == format::PipelineKind::compute ? gl_dearchiver.unpack_compute(p.name)
                                                             : gl_dearchiver.unpack_graphics(p.name);
      ASSERT_TRUE(program) << p.name << ": " << program.error().message;
      EXPECT_NE((*program)->program, 0u);
      ++programs;
      const format::Pipeline* vulkan = nullptr;
      for (const format::Pipeline& v : contents.pipelines)
        if (v.name == p.name) vulkan = &v;
      ASSERT_NE(vulkan, nullptr) << p.name;
      for (uint32_t set : vulkan->set_layouts) {
        if (set == format::kNone) continue;
        for (const format::Binding& b : contents.set_layouts[set].bindings) {
          if (b.descriptor_type == VK_DESCRIPTOR_TYPE_SAMPLER) continue;  // part of a texture on GL
          EXPECT_NE((*program)->find_binding(b.name), nullptr) << p.name << ": " << b.name;
        }
      }
      // Push constants are the uniform block $PushConstants on OpenGL; inline constants keep their own
      // name there (corpus/valid/inline_constants.json's are DrawConstants), as Diligent's OpenGL has them.
      if (vulkan->push_constant_size > 0) {
        EXPECT_TRUE((*program)->find_binding("$PushConstants") || (*program)->find_binding("DrawConstants"))
            << p.name;
      }
    }
  }
  EXPECT_GT(programs, 10u);
}

}  // namespace
}  // namespace statepack::testing
