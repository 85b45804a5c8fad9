// Variants files: the patched pipelines an application made, written by the Dearchiver, read back, and
// made again (by another Dearchiver, and by `statepack verify --variants`, which warms a cache with them).
#include <algorithm>

#include "common/run_command.hpp"
#include "common/text_files.hpp"
#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

namespace fs = std::filesystem;

class Variants : public VulkanTest {
 protected:
  Dearchiver dearchiver() {
    auto d = Dearchiver::create(vk_->device_context());
    EXPECT_TRUE(d) << d.error().message;
    for (const char* path : {STATEPACK_RUN_TIME_FORMATS_ARCHIVE, STATEPACK_SPECIALIZATION_ARCHIVE})
      EXPECT_TRUE(d->add_archive(Archive::from_file(path).value()));
    return std::move(d.value());
  }
  fs::path dir_;
  void SetUp() override {
    VulkanTest::SetUp();
    // One folder per test: ctest runs the tests of this fixture at once.
    dir_ = fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "variants");
  }
};

void swapchain(PatchableState& s, VkFormat format) {
  s.color_formats[0] = format;
}

TEST_F(Variants, WhatTheApplicationMadeIsWrittenReadAndMadeAgain) {
  Dearchiver first = dearchiver();
  // Swapchain recreation (twice the same format), an HDR toggle with blending, and a constant.
  for (VkFormat f : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM})
    ASSERT_TRUE(first.unpack_graphics("Swapchain Gradient PSO", [&](PatchableState& s) { swapchain(s, f); }));
  ASSERT_TRUE(first.unpack_graphics("Swapchain Gradient PSO", [](PatchableState& s) {
    swapchain(s, VK_FORMAT_R16G16B16A16_SFLOAT);
    s.blend[0].enable = true;
    s.blend[0].src_color = VK_BLEND_FACTOR_SRC_ALPHA;
    s.rasterizer.depth_bias = -0.5f;
  }));
  ASSERT_TRUE(
      first.unpack_compute("Seven", [](PatchableState& s) { ASSERT_TRUE(s.set_constant("kBase", 8u)); }));
  ASSERT_TRUE(first.unpack_compute("Seven"));                            // not a variant
  ASSERT_TRUE(first.unpack_compute("Negated", [](PatchableState&) {}));  // a variant with no change

  const std::vector<PipelineVariant> made = first.variants();
  ASSERT_EQ(made.size(), 4u);
  EXPECT_EQ(made[0].pipeline, "Swapchain Gradient PSO");
  EXPECT_EQ(made[0].kind, ObjectKind::graphics_pipeline);
  EXPECT_EQ(made[0].state, R"({"color_formats.0":"VK_FORMAT_B8G8R8A8_UNORM"})");
  EXPECT_EQ(made[1].state,
            R"({"color_formats.0":"VK_FORMAT_R16G16B16A16_SFLOAT","blend.0.enable":true,)"
            R"("blend.0.src_color":"VK_BLEND_FACTOR_SRC_ALPHA","rasterizer.depth_bias":-0.5})");
  EXPECT_EQ(made[2].pipeline, "Seven");
  EXPECT_EQ(made[2].kind, ObjectKind::compute_pipeline);
  EXPECT_EQ(made[2].state, R"({"constants":{"kBase":8}})");
  EXPECT_EQ(made[3].state, "{}");

  const fs::path file = dir_ / "variants.json";
  ASSERT_TRUE(first.save_variants(file));
  auto loaded = load_variants(file);
  ASSERT_TRUE(loaded) << loaded.error().message;
  ASSERT_EQ(loaded->size(), made.size());
  for (size_t i = 0; i < made.size(); ++i) {
    EXPECT_EQ((*loaded)[i].pipeline, made[i].pipeline);
    EXPECT_EQ((*loaded)[i].kind, made[i].kind);
    EXPECT_EQ((*loaded)[i].state, made[i].state);
  }
  // Another Dearchiver (the next run of the application, or a build step) makes the same variants.
  Dearchiver second = dearchiver();
  for (const PipelineVariant& v : *loaded) {
    auto pso = second.unpack_variant(v);
    ASSERT_TRUE(pso) << pso.error().message;
  }
  const std::vector<PipelineVariant> again = second.variants();
  ASSERT_EQ(again.size(), made.size());
  for (size_t i = 0; i < made.size(); ++i) EXPECT_EQ(again[i].state, made[i].state);
  // And the variant is the very pipeline the application's own callback makes.
  auto same = second.unpack_graphics("Swapchain Gradient PSO",
                                     [](PatchableState& s) { swapchain(s, VK_FORMAT_B8G8R8A8_UNORM); });
  ASSERT_TRUE(same);
  EXPECT_EQ(second.variants().size(), made.size());

  // statepack verify creates exactly those and warms a cache for them.
  const fs::path cache = dir_ / "warm.cache";
  CommandResult verify = run_command("'" STATEPACK_EXE "' verify '" STATEPACK_RUN_TIME_FORMATS_ARCHIVE
                                     "' '" STATEPACK_SPECIALIZATION_ARCHIVE "' --variants '" +
                                     file.string() + "' --cache '" + cache.string() + "'");
  EXPECT_EQ(verify.exit_code, 0) << verify.output;
  EXPECT_EQ(std::count(verify.output.begin(), verify.output.end(), '\n'), 10) << verify.output;
  for (const char* line : {"ok     graphics pipeline 'Swapchain Gradient PSO' with "
                           "{\"color_formats.0\":\"VK_FORMAT_B8G8R8A8_UNORM\"}: "
                           "created in ",
                           "ok     compute pipeline 'Seven' with {\"constants\":{\"kBase\":8}}: created in ",
                           "ok     compute pipeline 'Negated' as archived: created in ",
                           "run_time_formats.spk: 2 of 2 objects ok; 2 pipelines",
                           "specialization.spk: 2 of 2 objects ok; 2 pipelines",
                           "in all: 4 of 4 objects ok; 4 pipelines created in "})
    EXPECT_NE(verify.output.find(line), std::string::npos) << line << "\nnot in\n" << verify.output;
  EXPECT_TRUE(fs::exists(cache));
}

TEST_F(Variants, AVariantThatDoesNotFitItsPipelineIsAnErrorNamingIt) {
  Dearchiver d = dearchiver();
  auto unknown_constant =
      d.unpack_variant({"Seven", ObjectKind::compute_pipeline, R"({"constants":{"kBse":1}})"});
  ASSERT_FALSE(unknown_constant);
  EXPECT_EQ(unknown_constant.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(
      unknown_constant.error().message,
      "variant of pipeline 'Seven': state/constants/kBse: the pipeline has no specialization constant named "
      "'kBse' (did you mean 'kBase'?)");
  auto too_wide =
      d.unpack_variant({"Seven", ObjectKind::compute_pipeline, R"({"constants":{"kBase":4294967296}})"});
  ASSERT_FALSE(too_wide);
  EXPECT_NE(too_wide.error().message.find("does not fit the constant's 4 bytes"), std::string::npos);
  auto wrong_kind = d.unpack_variant({"Seven", ObjectKind::graphics_pipeline, "{}"});
  ASSERT_FALSE(wrong_kind);
  EXPECT_EQ(wrong_kind.error().code, ErrorCode::wrong_type);
  // A value the callback could not set either: checked as the callback's would be.
  auto depth_as_color = d.unpack_variant({"Swapchain Gradient PSO", ObjectKind::graphics_pipeline,
                                          R"({"color_formats.0":"VK_FORMAT_D32_SFLOAT"})"});
  ASSERT_FALSE(depth_as_color);
  EXPECT_EQ(depth_as_color.error().code, ErrorCode::invalid_argument);
  EXPECT_NE(depth_as_color.error().message.find("VK_FORMAT_D32_SFLOAT"), std::string::npos);
}

// Files nobody should trust: every mistake is named with the file, the JSON pointer and the reason.
TEST(VariantsFile, MistakesAreNamedWithTheirPlace) {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {R"([])", "variants file 'v.json' at /: expected an object"},
      {R"({"statepack_variants": 1, "variant": []})",
       "variants file 'v.json' at /variant: unknown key (did you mean 'variants'?)"},
      {R"({"variants": []})",
       "variants file 'v.json' at /statepack_variants: missing, or not a version number (this reader writes "
       "1)"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "mesh"}]})",
       "variants file 'v.json' at /variants/0/kind: expected \"graphics\" or \"compute\""},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "state": {"color_format.0": 1}}]})",
       "variants file 'v.json' at /variants/0/state/color_format.0: no such field (did you mean "
       "'color_formats.0'"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "state": {"samples": "VK_SAMPLE_COUNT_3_BIT"}}]})",
       "variants file 'v.json' at /variants/0/state/samples: 'VK_SAMPLE_COUNT_3_BIT' is not a "
       "VkSampleCountFlagBits name (did you mean 'VK_SAMPLE_COUNT_1_BIT'"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "state": {"color_formats.1": "VK_FORMAT_B8G8R8A8_SRBG"}}]})",
       "variants file 'v.json' at /variants/0/state/color_formats.1: 'VK_FORMAT_B8G8R8A8_SRBG' is not a "
       "VkFormat name (did you mean 'VK_FORMAT_B8G8R8A8_SRGB'"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "state": {"samples": 4}}]})",
       "variants file 'v.json' at /variants/0/state/samples: expected a VkSampleCountFlagBits name, such as "
       "VK_SAMPLE_COUNT_1_BIT"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "state": {"rasterizer.depth_bias": "x"}}]})",
       "variants file 'v.json' at /variants/0/state/rasterizer.depth_bias: expected a finite number"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "state": {"color_count": -1}}]})",
       "variants file 'v.json' at /variants/0/state/color_count: expected an unsigned 32-bit integer"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "compute", "state": {"color_count": 1}}]})",
       "variants file 'v.json' at /variants/0/state/color_count: a compute pipeline's variant sets only "
       "constants"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "state": {"dynamic_states": ["VK_DYNAMIC_STATE_VIEWPORT", 3]}}]})",
       "variants file 'v.json' at /variants/0/state/dynamic_states/1: expected a VkDynamicState name, such "
       "as "
       "VK_DYNAMIC_STATE_VIEWPORT"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "compute", "state": {"constants": {"a/b": -2}}}]})",
       "variants file 'v.json' at /variants/0/state/constants/a~1b: expected the value's bits as an unsigned "
       "integer"},
      {R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "extra": 1}]})",
       "variants file 'v.json' at /variants/0/extra: unknown key"},
      {R"({"statepack_variants": 1, "variants": )",
       "variants file 'v.json': parse error at line 1, column 39"},
  };
  for (const Case& c : cases) {
    auto parsed = parse_variants(c.text, "v.json");
    ASSERT_FALSE(parsed) << c.text;
    EXPECT_EQ(parsed.error().code, ErrorCode::invalid_argument) << c.text;
    EXPECT_TRUE(parsed.error().message.starts_with(c.message)) << c.text << "\n" << parsed.error().message;
  }
  auto newer = parse_variants(R"({"statepack_variants": 2, "variants": []})", "v.json");
  ASSERT_FALSE(newer);
  EXPECT_EQ(newer.error().code, ErrorCode::unsupported_version);
  std::string deep =
      R"({"statepack_variants": 1, "variants": [{"pipeline": "A", "kind": "graphics", "state": )";
  for (int i = 0; i < 100000; ++i) deep += "[";
  auto too_deep = parse_variants(deep, "v.json");
  ASSERT_FALSE(too_deep);
  EXPECT_NE(too_deep.error().message.find("nested deeper than 16 levels"), std::string::npos);
  // Names from the file are escaped before they reach a message.
  auto control = parse_variants(
      "{\"statepack_variants\": 1, \"variants\": [{\"pipeline\": \"A\", \"kind\": \"x\\u001b[31m\"}]}",
      "v\x1b.json");
  ASSERT_FALSE(control);
  EXPECT_EQ(control.error().message.find('\x1b'), std::string::npos) << control.error().message;
  // A directory, a FIFO or a missing file is an I/O error naming it, without blocking.
  auto missing = load_variants("/nonexistent/variants.json");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, ErrorCode::io_error);
  auto directory = load_variants("/tmp");
  ASSERT_FALSE(directory);
  EXPECT_EQ(directory.error().code, ErrorCode::io_error);
}

}  // namespace
}  // namespace statepack::testing
