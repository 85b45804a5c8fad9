// unpack_all with a patch callback: every pipeline's state passes through one callback that is told the
// pipeline's name and kind, and what it sets is checked exactly as unpack_graphics/unpack_compute check a
// modify callback's state. The archive (tests/data/run_time_formats) leaves two render targets UNKNOWN, as
// an application does for its swapchain's format.
#include <cmath>
#include <map>
#include <new>
#include <set>
#include <stdexcept>

#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

constexpr const char* kSwapchain = "Swapchain Gradient PSO";  // RTVFormats 0: UNKNOWN
constexpr const char* kOverlay = "Overlay Gradient PSO";      // RTVFormats 0: UNKNOWN
constexpr const char* kOffscreen = "Offscreen Gradient PSO";  // RTVFormats 0: RGBA8_UNORM
constexpr const char* kCompute = "Fill Buffer PSO";

class UnpackAllPatch : public VulkanTest {
 protected:
  // The archive's pipelines by name, read from the archive itself before it is handed over.
  std::map<std::string, ObjectKind> pipelines_;

  Dearchiver make_run_time_formats_dearchiver() {
    auto archive = Archive::from_file(STATEPACK_RUN_TIME_FORMATS_ARCHIVE);
    EXPECT_TRUE(archive) << archive.error().message;
    pipelines_.clear();
    for (const auto& o : archive->objects())
      if (o.kind == ObjectKind::graphics_pipeline || o.kind == ObjectKind::compute_pipeline)
        pipelines_.emplace(o.name, o.kind);
    auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
    EXPECT_TRUE(dearchiver) << dearchiver.error().message;
    EXPECT_TRUE(dearchiver->add_archive(std::move(*archive)));
    return std::move(dearchiver.value());
  }

  // What an application's callback does: every render target left UNKNOWN gets the swapchain's format.
  static void set_swapchain_format(PatchableState& s) {
    for (uint32_t i = 0; i < s.color_count; ++i)
      if (s.color_formats[i] == VK_FORMAT_UNDEFINED) s.color_formats[i] = VK_FORMAT_B8G8R8A8_UNORM;
  }

  static const UnpackedPipeline* named(const std::vector<const UnpackedPipeline*>& list,
                                       std::string_view name) {
    for (const UnpackedPipeline* p : list)
      if (p->name == name) return p;
    return nullptr;
  }

  // gradient.frag writes (u, v, 0.25, 1), u and v the pixel centre in 0..1. `bgra`: stored blue first.
  static void expect_gradient(const std::vector<uint8_t>& pixels, uint32_t width, uint32_t height, bool bgra,
                              const std::string& what) {
    ASSERT_EQ(pixels.size(), size_t(width) * height * 4) << what;
    auto unorm = [](double v) { return int(std::lround(v * 255.0)); };
    for (uint32_t y = 0; y < height; ++y) {
      for (uint32_t x = 0; x < width; ++x) {
        const int r = unorm((x + 0.5) / width), g = unorm((y + 0.5) / height), b = unorm(0.25);
        const std::array<int, 4> want = bgra ? std::array{b, g, r, 255} : std::array{r, g, b, 255};
        const uint8_t* got = &pixels[(size_t(y) * width + x) * 4];
        for (int c = 0; c < 4; ++c)
          ASSERT_NEAR(got[c], want[c], 1) << what << ": pixel (" << x << ", " << y << ") channel " << c;
      }
    }
  }
};

TEST_F(UnpackAllPatch, OneCallbackSetsTheSwapchainFormatOfEveryPipelineThatLeftItUnknown) {
  Dearchiver dearchiver = make_run_time_formats_dearchiver();
  ASSERT_EQ(pipelines_.size(), 4u);
  std::map<std::string, int> calls;
  std::map<std::string, ObjectKind> kinds;
  auto all = dearchiver.unpack_all(
      [&](const ObjectInfo& pipeline, PatchableState& s) {
        ++calls[pipeline.name];
        kinds[pipeline.name] = pipeline.kind;
        set_swapchain_format(s);
      },
      2);
  ASSERT_TRUE(all) << all.error().message;
  // Called once for each pipeline, with its name and kind, and for nothing else.
  EXPECT_EQ(kinds, pipelines_);
  for (const auto& [name, count] : calls) EXPECT_EQ(count, 1) << name;
  ASSERT_EQ(all->size(), 4u);
  for (const UnpackedPipeline* p : *all) EXPECT_NE(p->pipeline, VK_NULL_HANDLE) << p->name;

  // The pipelines really target the formats the callback left: the patched ones draw into a BGRA image
  // (same colours, stored blue first), the one the archive fixed as RGBA into an RGBA image.
  constexpr uint32_t kWidth = 16, kHeight = 12;
  for (const char* name : {kSwapchain, kOverlay}) {
    const UnpackedPipeline* pso = named(*all, name);
    ASSERT_NE(pso, nullptr) << name;
    expect_gradient(render_fullscreen(*pso, VK_FORMAT_B8G8R8A8_UNORM, kWidth, kHeight), kWidth, kHeight,
                    /*bgra*/ true, name);
  }
  const UnpackedPipeline* offscreen = named(*all, kOffscreen);
  ASSERT_NE(offscreen, nullptr);
  expect_gradient(render_fullscreen(*offscreen, VK_FORMAT_R8G8B8A8_UNORM, kWidth, kHeight), kWidth, kHeight,
                  /*bgra*/ false, kOffscreen);
  const UnpackedPipeline* compute = named(*all, kCompute);
  ASSERT_NE(compute, nullptr);
  EXPECT_EQ(compute->bind_point, VK_PIPELINE_BIND_POINT_COMPUTE);

  // A second call sees every pipeline again; the same patch settles the same states, so it returns
  // the same pipelines (variants are keyed by the settled state) rather than creating them anew.
  calls.clear();
  auto again = dearchiver.unpack_all([&](const ObjectInfo& pipeline, PatchableState& s) {
    ++calls[pipeline.name];
    set_swapchain_format(s);
  });
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(calls.size(), 4u);
  for (const UnpackedPipeline* p : *again) EXPECT_EQ(named(*all, p->name)->pipeline, p->pipeline) << p->name;
}

TEST_F(UnpackAllPatch, AFormatLeftUnknownIsAnErrorNamingThePipelineAndSlot) {
  Dearchiver dearchiver = make_run_time_formats_dearchiver();
  // The old signature, no callback: every pipeline with an UNKNOWN target is named, in archive order.
  auto unpatched = dearchiver.unpack_all();
  ASSERT_FALSE(unpatched);
  EXPECT_EQ(unpatched.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(
      unpatched.error().message,
      "2 objects failed: pipeline 'Overlay Gradient PSO': render target 0 is UNKNOWN (a format set at run "
      "time); set PatchableState::color_formats[0] in the modify callback, or give RTVFormats[0] in the "
      "notation and pack again; pipeline 'Swapchain Gradient PSO': render target 0 is UNKNOWN (a format set "
      "at run time); set PatchableState::color_formats[0] "
      "in the modify callback, or give RTVFormats[0] in the notation and pack again");
  // A callback that patches one of the two leaves the other one's slot named.
  auto half = dearchiver.unpack_all([](const ObjectInfo& pipeline, PatchableState& s) {
    if (pipeline.name == kOverlay) set_swapchain_format(s);
  });
  ASSERT_FALSE(half);
  EXPECT_EQ(half.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(
      half.error().message,
      "pipeline 'Swapchain Gradient PSO': render target 0 is UNKNOWN (a format set at run time); set "
      "PatchableState::color_formats[0] in the modify callback, or give RTVFormats[0] in the notation and "
      "pack again");
}

// Variants: a patched unpack is keyed by the state the callback settled, not by the callback, so a
// swapchain recreated a thousand times, or toggled between two formats, makes one pipeline per format.
TEST_F(UnpackAllPatch, TheSameSettledStateIsTheSamePipelineWhateverTheCallback) {
  Dearchiver dearchiver = make_run_time_formats_dearchiver();
  auto first = dearchiver.unpack_graphics(kSwapchain, set_swapchain_format);
  ASSERT_TRUE(first) << first.error().message;
  auto again = dearchiver.unpack_graphics(kSwapchain, [](PatchableState& s) {
    s.color_formats[0] = VK_FORMAT_B8G8R8A8_UNORM;  // another callback, the same result
    s.dynamic_states = {s.dynamic_states.rbegin(), s.dynamic_states.rend()};  // order means nothing
  });
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(*again, *first);
  EXPECT_EQ((*again)->pipeline, (*first)->pipeline);
  auto other = dearchiver.unpack_graphics(
      kSwapchain, [](PatchableState& s) { s.color_formats[0] = VK_FORMAT_R8G8B8A8_UNORM; });
  ASSERT_TRUE(other) << other.error().message;
  EXPECT_NE(*other, *first);
  EXPECT_NE((*other)->pipeline, (*first)->pipeline);
  // unpack_all with the same patch reuses the variants made one by one.
  auto all = dearchiver.unpack_all([](const ObjectInfo&, PatchableState& s) { set_swapchain_format(s); });
  ASSERT_TRUE(all) << all.error().message;
  EXPECT_EQ(named(*all, kSwapchain), *first);
}

TEST_F(UnpackAllPatch, AlternatingPatchesKeepOnePipelinePerStateAndReleaseFreesThem) {
  Dearchiver dearchiver = make_run_time_formats_dearchiver();
  std::set<const UnpackedPipeline*> objects;
  std::set<VkPipeline> handles;
  for (int i = 0; i < 1000; ++i) {
    const VkFormat format = i % 2 ? VK_FORMAT_B8G8R8A8_UNORM : VK_FORMAT_R8G8B8A8_SRGB;
    auto p = dearchiver.unpack_graphics(kSwapchain, [&](PatchableState& s) { s.color_formats[0] = format; });
    ASSERT_TRUE(p) << p.error().message;
    objects.insert(*p);
    handles.insert((*p)->pipeline);
  }
  EXPECT_EQ(objects.size(), 2u);
  EXPECT_EQ(handles.size(), 2u);
  // Released: destroyed now (the layer would report a double destroy at the Dearchiver's end, or a
  // leak at the device's), refused a second time, and made anew by the next unpack of that state.
  for (const UnpackedPipeline* p : objects) EXPECT_TRUE(dearchiver.release(p));
  auto twice = dearchiver.release(*objects.begin());
  ASSERT_FALSE(twice);
  EXPECT_EQ(twice.error().code, ErrorCode::invalid_argument);
  auto remade = dearchiver.unpack_graphics(kSwapchain, set_swapchain_format);
  ASSERT_TRUE(remade) << remade.error().message;
  EXPECT_NE((*remade)->pipeline, VkPipeline(VK_NULL_HANDLE));
  // An unpatched pipeline can be released too; unpacking it again creates it again.
  auto plain = dearchiver.unpack_graphics(kOffscreen);
  ASSERT_TRUE(plain) << plain.error().message;
  EXPECT_TRUE(dearchiver.release(*plain));
  auto plain_again = dearchiver.unpack_graphics(kOffscreen);
  ASSERT_TRUE(plain_again) << plain_again.error().message;
  EXPECT_NE((*plain_again)->pipeline, VkPipeline(VK_NULL_HANDLE));
}

// A value Vulkan forbids on every device is the caller's mistake, in Vulkan's words; one this device
// cannot do is `unsupported`.
TEST_F(UnpackAllPatch, FormatsInTheWrongSlotAreTheCallersMistakeInVulkansWords) {
  Dearchiver dearchiver = make_run_time_formats_dearchiver();
  auto depth_as_colour = dearchiver.unpack_graphics(
      kOffscreen, [](PatchableState& s) { s.color_formats[0] = VK_FORMAT_D32_SFLOAT; });
  ASSERT_FALSE(depth_as_colour);
  EXPECT_EQ(depth_as_colour.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(depth_as_colour.error().message,
            "pipeline 'Offscreen Gradient PSO': the modify callback set PatchableState::color_formats[0] to "
            "VK_FORMAT_D32_SFLOAT, a depth-stencil format, which cannot be a colour render target");
  auto compressed = dearchiver.unpack_graphics(
      kOffscreen, [](PatchableState& s) { s.color_formats[0] = VK_FORMAT_BC1_RGB_UNORM_BLOCK; });
  ASSERT_FALSE(compressed);
  EXPECT_EQ(compressed.error().code, ErrorCode::unsupported);
  EXPECT_EQ(
      compressed.error().message,
      "pipeline 'Offscreen Gradient PSO': render target 0 has format VK_FORMAT_BC1_RGB_UNORM_BLOCK, which "
      "the device cannot render to");
}

// Each bad patch fails unpack_all with the error unpack_graphics/unpack_compute give for the same modify
// callback: the values are checked by the same code before they reach Vulkan (the fixture fails the test
// on any validation message).
TEST_F(UnpackAllPatch, PatchedValuesPassTheSingleObjectChecks) {
  struct BadPatch {
    const char* pipeline;
    std::function<void(PatchableState&)> edit;
    const char* expected;  // part of the error, so that each patch is refused for its own reason
  };
  const BadPatch patches[] = {
      {kSwapchain, [](PatchableState& s) { s.color_count = 9; }, "color_count to 9, which is not 8 or fewer"},
      {kSwapchain, [](PatchableState& s) { s.color_formats[0] = VkFormat(0x7FFF0000); },
       "color_formats[0] to 2147418112, which is not a Vulkan 1.0 format"},
      {kOffscreen, [](PatchableState& s) { s.color_formats[0] = VK_FORMAT_D32_SFLOAT; },
       "the modify callback set PatchableState::color_formats[0] to VK_FORMAT_D32_SFLOAT, a depth-stencil "
       "format, "
       "which cannot be a colour render target"},
      {kOffscreen, [](PatchableState& s) { s.depth_stencil_format = VK_FORMAT_R8G8B8A8_UNORM; },
       "the modify callback set PatchableState::depth_stencil_format to VK_FORMAT_R8G8B8A8_UNORM, which has "
       "no "
       "depth or stencil component"},
      {kOffscreen, [](PatchableState& s) { s.color_formats[0] = VK_FORMAT_BC1_RGB_UNORM_BLOCK; },
       "render target 0 has format VK_FORMAT_BC1_RGB_UNORM_BLOCK, which the device cannot render to"},
      {kOffscreen, [](PatchableState& s) { s.blend[0].src_color = VkBlendFactor(99); },
       "blend[0].src_color to 99, which is not a VkBlendFactor"},
      {kOverlay, [](PatchableState& s) { s.samples = VkSampleCountFlagBits(3); },
       "samples to 3, which is not one VkSampleCountFlagBits"},
      {kOverlay, [](PatchableState& s) { s.samples = VK_SAMPLE_COUNT_64_BIT; }, "renders with 64 samples"},
      {kSwapchain, [](PatchableState& s) { s.rasterizer.polygon_mode = VkPolygonMode(9); },
       "rasterizer.polygon_mode to 9, which is not a VkPolygonMode"},
      {kSwapchain, [](PatchableState& s) { s.rasterizer.depth_bias_slope = std::nanf(""); },
       "rasterizer.depth_bias_slope to nan, which is not a finite number"},
      {kSwapchain, [](PatchableState& s) { s.rasterizer.depth_bias = -INFINITY; },
       "rasterizer.depth_bias to -inf, which is not a finite number"},
      {kSwapchain, [](PatchableState& s) { s.depth_stencil.front.compareOp = VkCompareOp(8); },
       "depth_stencil.front.compareOp to 8, which is not a VkCompareOp"},
      {kSwapchain, [](PatchableState& s) { std::erase(s.dynamic_states, VK_DYNAMIC_STATE_VIEWPORT); },
       "viewport and scissor must stay dynamic"},
      {kOverlay, [](PatchableState& s) { s.dynamic_states.push_back(VK_DYNAMIC_STATE_VERTEX_INPUT_EXT); },
       "is not supported by the dearchiver"},
      {kCompute,
       [](PatchableState& s) {
         s.constants.push_back({"kInvented", VK_SHADER_STAGE_COMPUTE_BIT, 4, {}});
       },
       "has no specialization constant 'kInvented'"},
  };
  for (const BadPatch& bad : patches) {
    SCOPED_TRACE(bad.expected);
    Dearchiver single_dearchiver = make_run_time_formats_dearchiver();
    auto modify = [&](PatchableState& s) {
      set_swapchain_format(s);
      bad.edit(s);
    };
    auto single = pipelines_.at(bad.pipeline) == ObjectKind::compute_pipeline
                      ? single_dearchiver.unpack_compute(bad.pipeline, modify)
                      : single_dearchiver.unpack_graphics(bad.pipeline, modify);
    ASSERT_FALSE(single);

    Dearchiver all_dearchiver = make_run_time_formats_dearchiver();
    auto all = all_dearchiver.unpack_all([&](const ObjectInfo& pipeline, PatchableState& s) {
      if (pipeline.name == bad.pipeline)
        modify(s);
      else
        set_swapchain_format(s);
    });
    ASSERT_FALSE(all);
    EXPECT_EQ(all.error().code, single.error().code);
    EXPECT_EQ(all.error().message, single.error().message);
    EXPECT_NE(all.error().message.find("pipeline '" + std::string(bad.pipeline) + "'"), std::string::npos)
        << all.error().message;
    EXPECT_NE(all.error().message.find(bad.expected), std::string::npos) << all.error().message;
  }
}

TEST_F(UnpackAllPatch, CallbackExceptionsBecomeErrorsNamingThePipeline) {
  Dearchiver dearchiver = make_run_time_formats_dearchiver();
  auto thrown = dearchiver.unpack_all([](const ObjectInfo& pipeline, PatchableState& s) {
    set_swapchain_format(s);
    if (pipeline.name == kOverlay) throw std::runtime_error("no swapchain yet");
  });
  ASSERT_FALSE(thrown);
  EXPECT_EQ(thrown.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(thrown.error().message,
            "pipeline 'Overlay Gradient PSO': the modify callback threw: no swapchain yet");

  auto not_an_exception = dearchiver.unpack_all([](const ObjectInfo& pipeline, PatchableState&) {
    if (pipeline.kind == ObjectKind::compute_pipeline) throw 42;
  });
  ASSERT_FALSE(not_an_exception);
  EXPECT_EQ(not_an_exception.error().code, ErrorCode::invalid_argument);
  EXPECT_TRUE(not_an_exception.error().message.starts_with(
      "3 objects failed: pipeline 'Fill Buffer PSO': the modify callback threw; "))
      << not_an_exception.error().message;

  auto out_of_memory =
      dearchiver.unpack_all([](const ObjectInfo&, PatchableState&) { throw std::bad_alloc(); });
  ASSERT_FALSE(out_of_memory);
  EXPECT_EQ(out_of_memory.error().code, ErrorCode::out_of_memory);

  // Nothing was left half made: the same dearchiver unpacks everything afterwards.
  auto after = dearchiver.unpack_all([](const ObjectInfo&, PatchableState& s) { set_swapchain_format(s); });
  ASSERT_TRUE(after) << after.error().message;
  EXPECT_EQ(after->size(), 4u);
}

// Diligent's workflow: the notation gives no render targets (Tutorial25's gives none), the callback sets
// count and format. Forgetting the patch is caught at unpack with the fix in the message, never a
// pipeline that silently draws nothing; and the callback is told which targets the pixel shader writes.
TEST_F(UnpackAllPatch, RenderTargetsLeftToRunTimeMustBeSetByTheCallback) {
  auto archive = Archive::from_file(STATEPACK_RUN_TIME_TARGETS_ARCHIVE);
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  constexpr const char* kName = "Targets Set At Run Time PSO";

  const std::string expected =
      "pipeline 'Targets Set At Run Time PSO': its pixel shader 'Gradient PS' writes render target 0, but "
      "the pipeline has 0 render target(s): the notation leaves them to run time, so set "
      "PatchableState::color_count (to at least 1) and color_formats in the modify callback, or give "
      "NumRenderTargets and RTVFormats in the notation and pack again";
  auto unpatched = dearchiver->unpack_graphics(kName);
  ASSERT_FALSE(unpatched);
  EXPECT_EQ(unpatched.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(unpatched.error().message, expected);
  // A callback that runs but forgets the count fails the same way; so does unpack_all.
  uint32_t written = 0;
  auto forgot = dearchiver->unpack_graphics(kName, [&](PatchableState& s) {
    written = s.written_color_targets;
    s.written_color_targets = 0;  // read only: changing it must not hide the mistake
  });
  ASSERT_FALSE(forgot);
  EXPECT_EQ(forgot.error().message, expected);
  EXPECT_EQ(written, 1u);
  auto all = dearchiver->unpack_all();
  ASSERT_FALSE(all);
  EXPECT_EQ(all.error().message, expected);
  // A count without a format is the UNKNOWN error, naming the slot.
  auto no_format = dearchiver->unpack_graphics(kName, [](PatchableState& s) { s.color_count = 1; });
  ASSERT_FALSE(no_format);
  EXPECT_NE(no_format.error().message.find("render target 0 is UNKNOWN"), std::string::npos)
      << no_format.error().message;
  // A format of the wrong numeric type from the callback is the caller's mistake (invalid_argument, as
  // every callback value), not a damaged archive (corrupt).
  auto wrong_type = dearchiver->unpack_graphics(kName, [](PatchableState& s) {
    s.color_count = 1;
    s.color_formats[0] = VK_FORMAT_R8G8B8A8_UINT;
  });
  ASSERT_FALSE(wrong_type);
  EXPECT_EQ(wrong_type.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(
      wrong_type.error().message,
      "pipeline 'Targets Set At Run Time PSO': render target 0 has format VK_FORMAT_R8G8B8A8_UINT (set by "
      "the modify callback), which holds unsigned integer values, but the shader's variable at location 0 "
      "is float");

  // Patched as Tutorial25's callback does, it draws the gradient into the target it was given.
  auto patched = dearchiver->unpack_graphics(kName, [](PatchableState& s) {
    s.color_count = 1;
    s.color_formats[0] = VK_FORMAT_B8G8R8A8_UNORM;
  });
  ASSERT_TRUE(patched) << patched.error().message;
  constexpr uint32_t kWidth = 16, kHeight = 12;
  expect_gradient(render_fullscreen(**patched, VK_FORMAT_B8G8R8A8_UNORM, kWidth, kHeight), kWidth, kHeight,
                  /*bgra*/ true, kName);
}

}  // namespace
}  // namespace statepack::testing
