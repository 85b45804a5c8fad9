// Dearchiver::reload and ArchiveFileWatch on lavapipe, with the validation layer on: a temporary project
// is packed by the real packer, edited and packed again, and the running pipelines are reloaded. What a
// reloaded pipeline computes or draws is read back: the same UnpackedPipeline pointer must run the new
// shader, an unchanged pipeline must keep its VkPipeline, and every failure must keep the old one.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "common/run_command.hpp"
#include "common/text_files.hpp"
#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

namespace fs = std::filesystem;

// A compute shader writing `value` (a macro of the notation, or the text itself) to Result.value.
std::string writer_shader(const std::string& value, const std::string& extra_binding = "") {
  return "#version 450\nlayout(local_size_x = 1) in;\n"
         "layout(constant_id = 0) const uint kBase = 0u;\n"
         "layout(set = 0, binding = 0) buffer Result { uint value; } result;\n" +
         extra_binding + "void main() { result.value = " + value + "; }\n";
}

std::string two_writers(const std::string& second_name = "B") {
  return R"({ "Pipelines": [
    { "PSODesc": { "Name": "A" }, "pCS": { "Desc": { "Name": "A CS" }, "FilePath": "a.comp" },
      "pSpecializationConstants": [ { "Name": "kBase", "Value": 0 } ] },
    { "PSODesc": { "Name": ")" +
         second_name + R"(" }, "pCS": { "Desc": { "Name": "B CS" }, "FilePath": "b.comp" } } ] })";
}

// A temporary project packed by the real packer, as `statepack pack --watch` would repack it.
class Project {
 public:
  explicit Project(const std::string& name) : dir_(fs::path(STATEPACK_TEST_OUTPUT_DIR) / ("reload_" + name)) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  // The pack command line of this project, writing `out` (its archive by default).
  std::string pack_command(const std::string& extra = "", const fs::path& out = {}) const {
    return "'" STATEPACK_EXE "' pack --vulkan " + extra + " -s '" + dir_.string() + "' -o '" +
           (out.empty() ? archive_path() : out).string() + "' -i '" + (dir_ / "states.json").string() + "'";
  }
  void write(const std::string& file, const std::string& text) const { write_file(dir_ / file, text); }
  fs::path archive_path() const { return dir_ / "out.spk"; }
  void pack(const std::string& extra = "") const {
    CommandResult r = run_command(pack_command(extra));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  Archive load() const {
    auto archive = Archive::from_file(archive_path());
    EXPECT_TRUE(archive) << archive.error().message;
    return std::move(*archive);
  }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

// The usual project: compute pipelines A and B writing `a` and `b` (GLSL expressions), packed.
Project writers(const std::string& name, const std::string& a, const std::string& b) {
  Project project(name);
  project.write("states.json", two_writers());
  project.write("a.comp", writer_shader(a));
  project.write("b.comp", writer_shader(b));
  project.pack();
  return project;
}

class ReloadTest : public VulkanTest {
 protected:
  Dearchiver dearchiver_for(const Project& project) {
    auto dearchiver = Dearchiver::create(vk_->device_context());
    EXPECT_TRUE(dearchiver) << dearchiver.error().message;
    EXPECT_TRUE(dearchiver->add_archive(project.load()));
    return std::move(*dearchiver);
  }
  // Runs a compute pipeline once through the pointer the application holds; returns what it wrote.
  uint32_t run(const UnpackedPipeline& pso) {
    const std::array<uint8_t, 16> bytes = dispatch_once(pso, "Result", 0xEE);
    uint32_t value = 0;
    std::memcpy(&value, bytes.data(), 4);
    return value;
  }
  const UnpackedPipeline* compute(Dearchiver& d, std::string_view name, const ModifyCallback& modify = {}) {
    auto made = d.unpack_compute(name, modify);
    EXPECT_TRUE(made) << made.error().message;
    return made ? *made : nullptr;
  }
};

TEST_F(ReloadTest, AnEditedShaderRunsThroughTheSamePointerAndTheOtherPipelineKeepsItsHandle) {
  Project project = writers("edit", "11u", "22u");
  Dearchiver d = dearchiver_for(project);
  const UnpackedPipeline* a = compute(d, "A");
  const UnpackedPipeline* b = compute(d, "B");
  ASSERT_TRUE(a && b);
  EXPECT_EQ(run(*a), 11u);
  const VkPipeline a_before = a->pipeline, b_before = b->pipeline;
  const VkPipelineLayout layout_before = a->layout;

  project.write("a.comp", writer_shader("33u"));
  project.pack();
  auto report = d.reload(project.load());
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_TRUE(report->ok());
  EXPECT_EQ(report->recreated, std::vector<std::string>{"A"});
  EXPECT_EQ(report->kept, std::vector<std::string>{"B"});
  EXPECT_TRUE(report->removed.empty() && report->added.empty());
  EXPECT_EQ(report->generation, 1u);
  EXPECT_EQ(d.reload_generation(), 1u);
  EXPECT_NE(a->pipeline, a_before);     // the same pointer, a new pipeline
  EXPECT_EQ(a->layout, layout_before);  // descriptor sets made for it still fit
  EXPECT_EQ(b->pipeline, b_before);
  EXPECT_EQ(run(*a), 33u);
  EXPECT_EQ(run(*b), 22u);
  auto again = d.unpack_compute("A");  // by name: the same, reloaded pipeline
  ASSERT_TRUE(again);
  EXPECT_EQ(*again, a);
  EXPECT_EQ(d.destroy_retired(), 1u);  // the GPU is idle: submit_and_wait waited
  EXPECT_EQ(d.destroy_retired(), 0u);

  // The same archive again: nothing changes, no generation.
  auto same = d.reload(project.load());
  ASSERT_TRUE(same);
  EXPECT_TRUE(same->recreated.empty());
  EXPECT_EQ(same->kept.size(), 2u);
  EXPECT_EQ(same->generation, 1u);
}

TEST_F(ReloadTest, AnIncludeOnlyChangeRecreatesThePipelinesThatIncludeIt) {
  Project project("include");
  project.write("states.json", two_writers());
  project.write("value.glsl", "#define VALUE 5u\n");
  project.write("a.comp",
                writer_shader("VALUE").insert(
                    13, "#extension GL_GOOGLE_include_directive : require\n#include \"value.glsl\"\n"));
  project.write("b.comp", writer_shader("7u"));
  project.pack();
  Dearchiver d = dearchiver_for(project);
  const UnpackedPipeline* a = compute(d, "A");
  const UnpackedPipeline* b = compute(d, "B");
  ASSERT_TRUE(a && b);
  EXPECT_EQ(run(*a), 5u);
  project.write("value.glsl", "#define VALUE 6u\n");
  project.pack();
  auto report = d.reload(project.load());
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_EQ(report->recreated, std::vector<std::string>{"A"});
  EXPECT_EQ(report->kept, std::vector<std::string>{"B"});
  EXPECT_EQ(run(*a), 6u);
}

TEST_F(ReloadTest, ANotationEditThatRenamesAPipelineReportsItRemovedAndAddedAndTheOldOneStillRuns) {
  Project project = writers("rename", "1u", "2u");
  Dearchiver d = dearchiver_for(project);
  const UnpackedPipeline* b = compute(d, "B");
  ASSERT_TRUE(b);
  project.write("states.json", two_writers("C"));
  project.pack();
  auto report = d.reload(project.load());
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_EQ(report->removed, std::vector<std::string>{"B"});
  EXPECT_EQ(report->added, std::vector<std::string>{"C"});
  EXPECT_EQ(run(*b), 2u);  // still the application's until released
  auto gone = d.unpack_compute("B");
  ASSERT_FALSE(gone);
  EXPECT_EQ(gone.error().code, ErrorCode::not_found);
  EXPECT_NE(gone.error().message.find("'C'"), std::string::npos) << gone.error().message;  // did you mean
  const UnpackedPipeline* c = compute(d, "C");
  ASSERT_TRUE(c);
  EXPECT_EQ(run(*c), 2u);
  EXPECT_TRUE(d.release(b));
  EXPECT_FALSE(d.release(b));
}

TEST_F(ReloadTest, ALayoutChangeIsALayoutChangedFailureNamingThePipelineAndTheOldOneStays) {
  Project project = writers("layout", "3u", "4u");
  Dearchiver d = dearchiver_for(project);
  const UnpackedPipeline* a = compute(d, "A");
  ASSERT_TRUE(a);
  const VkPipeline before = a->pipeline;
  project.write("a.comp", writer_shader("3u + extra.more",
                                        "layout(set = 0, binding = 1) buffer Extra { uint more; } extra;\n"));
  project.pack();
  auto report = d.reload(project.load());
  ASSERT_TRUE(report) << report.error().message;
  ASSERT_EQ(report->failures.size(), 1u);
  const Error& e = report->failures[0].error;
  EXPECT_EQ(e.code, ErrorCode::layout_changed);
  EXPECT_EQ(report->failures[0].object.name, "A");
  EXPECT_NE(e.message.find("pipeline 'A'"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("set 0 binding 1 was added"), std::string::npos) << e.message;
  EXPECT_TRUE(report->recreated.empty());
  EXPECT_EQ(a->pipeline, before);
  EXPECT_EQ(run(*a), 3u);
  auto by_name = d.unpack_compute("A");
  ASSERT_TRUE(by_name);
  EXPECT_EQ(*by_name, a);  // still the old one
  EXPECT_EQ(d.destroy_retired(), 0u);

  // Fixed on the next build: the pipeline made from the older build is compared again and re-created.
  project.write("a.comp", writer_shader("8u"));
  project.pack();
  auto fixed = d.reload(project.load());
  ASSERT_TRUE(fixed) << fixed.error().message;
  EXPECT_TRUE(fixed->ok());
  EXPECT_EQ(fixed->recreated, std::vector<std::string>{"A"});
  EXPECT_EQ(run(*a), 8u);
}

TEST_F(ReloadTest, APatchedPipelineIsRecreatedWithItsChangesAndAFailingPatchKeepsTheOldOne) {
  Project project = writers("patched", "kBase + 1u", "0u");
  Dearchiver d = dearchiver_for(project);
  const UnpackedPipeline* a =
      compute(d, "A", [](PatchableState& s) { EXPECT_TRUE(s.set_constant("kBase", 100u)); });
  ASSERT_TRUE(a);
  EXPECT_EQ(run(*a), 101u);

  project.write("a.comp", writer_shader("kBase + 2u"));
  project.pack();
  // A reload patch that throws: named, the old pipeline stays.
  ReloadOptions failing;
  failing.patch = [](const ObjectInfo&, PatchableState&) { throw std::runtime_error("no swapchain yet"); };
  auto refused = d.reload(project.load(), failing);
  ASSERT_TRUE(refused) << refused.error().message;
  ASSERT_EQ(refused->failures.size(), 1u);
  EXPECT_NE(refused->failures[0].error.message.find("'A'"), std::string::npos)
      << refused->failures[0].error.message;
  EXPECT_NE(refused->failures[0].error.message.find("no swapchain yet"), std::string::npos)
      << refused->failures[0].error.message;
  EXPECT_EQ(run(*a), 101u);

  // Without it the recorded change (kBase = 100) is applied to the new build.
  auto report = d.reload(project.load());
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_EQ(report->recreated, std::vector<std::string>{"A"});
  EXPECT_EQ(run(*a), 102u);
  // And a reload patch may change more.
  project.write("a.comp", writer_shader("kBase + 3u"));
  project.pack();
  ReloadOptions more;
  more.patch = [](const ObjectInfo& p, PatchableState& s) {
    EXPECT_EQ(p.name, "A");
    EXPECT_EQ(s.find_constant("kBase")->get<uint32_t>(), 100u);
    s.set_constant("kBase", 200u);
  };
  auto patched = d.reload(project.load(), more);
  ASSERT_TRUE(patched) << patched.error().message;
  EXPECT_EQ(run(*a), 203u);
  auto variants = d.variants();
  ASSERT_EQ(variants.size(), 1u);
  EXPECT_NE(variants[0].state.find("200"), std::string::npos) << variants[0].state;
}

TEST_F(ReloadTest, AnotherContentVersionIsRefusedUnlessAllowed) {
  Project project("content_version");
  project.write("states.json", two_writers());
  project.write("a.comp", writer_shader("1u"));
  project.write("b.comp", writer_shader("2u"));
  project.pack("-v 1");
  Dearchiver d = dearchiver_for(project);
  const UnpackedPipeline* a = compute(d, "A");
  ASSERT_TRUE(a);
  project.write("a.comp", writer_shader("9u"));
  project.pack("-v 2");
  auto refused = d.reload(project.load());
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().code, ErrorCode::content_version_mismatch);
  EXPECT_NE(refused.error().message.find("content version is 2"), std::string::npos)
      << refused.error().message;
  EXPECT_EQ(run(*a), 1u);
  ReloadOptions allow;
  allow.allow_content_version_change = true;
  auto accepted = d.reload(project.load(), allow);
  ASSERT_TRUE(accepted) << accepted.error().message;
  EXPECT_EQ(run(*a), 9u);
  ReloadOptions wrong;
  wrong.archive = 1;
  auto bad_index = d.reload(project.load(), wrong);
  ASSERT_FALSE(bad_index);
  EXPECT_EQ(bad_index.error().code, ErrorCode::invalid_argument);
}

TEST_F(ReloadTest, AReloadWhileAnUnpackJobRunsWaitsForItAndReloadsWhatItMade) {
  Project project("job");
  std::string states = R"({ "Pipelines": [)";
  for (int i = 0; i < 24; ++i)
    states += std::string(i ? "," : "") + R"({ "PSODesc": { "Name": "P)" + std::to_string(i) +
              R"(" }, "pCS": { "Desc": { "Name": "CS)" + std::to_string(i) + R"(" }, "FilePath": "p)" +
              std::to_string(i) + R"(.comp" } })";
  states += "] }";
  project.write("states.json", states);
  for (int i = 0; i < 24; ++i)
    project.write("p" + std::to_string(i) + ".comp", writer_shader(std::to_string(i) + "u"));
  project.pack();
  Dearchiver d = dearchiver_for(project);
  project.write("p5.comp", writer_shader("500u"));
  project.pack();
  auto job = d.unpack_all_async({});
  ASSERT_TRUE(job) << job.error().message;
  auto report = d.reload(project.load());  // while the job's threads create the pipelines
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_TRUE(report->ok());
  EXPECT_EQ(report->recreated, std::vector<std::string>{"P5"});
  EXPECT_EQ(report->kept.size(), 23u);
  UnpackReport made = job->wait_all();
  EXPECT_TRUE(made.ok());
  auto p5 = job->wait("P5");
  ASSERT_TRUE(p5);
  EXPECT_EQ(run(**p5), 500u);  // the job's pointer reads the reloaded pipeline
  EXPECT_EQ(run(*compute(d, "P6")), 6u);
}

TEST_F(ReloadTest, APatchedGraphicsPipelineIsRecreatedWithItsRunTimeFormatAndDrawsTheNewShader) {
  Project project("graphics");
  project.write("states.json", R"({ "Pipelines": [ {
    "PSODesc": { "Name": "Fill PSO" },
    "GraphicsPipeline": { "RasterizerDesc": { "CullMode": "NONE" }, "DepthStencilDesc": { "DepthEnable": false },
                          "NumRenderTargets": 1, "RTVFormats": { "0": "UNKNOWN" } },
    "pVS": { "Desc": { "Name": "VS" }, "FilePath": "fill.vert" },
    "pPS": { "Desc": { "Name": "PS" }, "FilePath": "fill.frag" } } ] })");
  project.write("fill.vert",
                "#version 450\nvoid main() { vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);\n"
                "gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0); }\n");
  auto fragment = [](const char* color) {
    return std::string("#version 450\nlayout(location = 0) out vec4 o;\nvoid main() { o = vec4(") + color +
           "); }\n";
  };
  project.write("fill.frag", fragment("1.0, 0.0, 0.0, 1.0"));
  project.pack();
  Dearchiver d = dearchiver_for(project);
  auto pso =
      d.unpack_graphics("Fill PSO", [](PatchableState& s) { s.color_formats[0] = VK_FORMAT_R8G8B8A8_UNORM; });
  ASSERT_TRUE(pso) << pso.error().message;
  auto pixels = render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, 4, 4);
  ASSERT_EQ(pixels.size(), 64u);
  EXPECT_EQ(std::vector<uint8_t>(pixels.begin(), pixels.begin() + 4), (std::vector<uint8_t>{255, 0, 0, 255}));

  project.write("fill.frag", fragment("0.0, 0.0, 1.0, 1.0"));
  project.pack();
  auto report = d.reload(project.load());
  ASSERT_TRUE(report) << report.error().message;
  ASSERT_TRUE(report->ok()) << report->failures[0].error.message;
  EXPECT_EQ(report->recreated, std::vector<std::string>{"Fill PSO"});
  pixels = render_fullscreen(**pso, VK_FORMAT_R8G8B8A8_UNORM, 4, 4);
  ASSERT_EQ(pixels.size(), 64u);
  EXPECT_EQ(std::vector<uint8_t>(pixels.begin() + 60, pixels.end()), (std::vector<uint8_t>{0, 0, 255, 255}));
}

// The binding table the application holds stays where it is, immutable samplers included; a change of
// render-target formats is refused as a layout change is.
TEST_F(ReloadTest, BindingPointersAndImmutableSamplersSurviveAReloadAndAFormatChangeIsRefused) {
  Project project("sampler");
  auto states = [](const char* format) {
    return std::string(R"({ "Pipelines": [ {
      "PSODesc": { "Name": "Textured PSO", "ResourceLayout": { "ImmutableSamplers": [ { "ShaderStages": "PIXEL",
        "SamplerOrTextureName": "tex", "Desc": { "MinFilter": "POINT", "MagFilter": "POINT", "MipFilter": "POINT" } } ] } },
      "GraphicsPipeline": { "RasterizerDesc": { "CullMode": "NONE" }, "DepthStencilDesc": { "DepthEnable": false },
                            "RTVFormats": { "0": ")") +
           format + R"(" } },
      "pVS": { "Desc": { "Name": "VS" }, "FilePath": "fill.vert" },
      "pPS": { "Desc": { "Name": "PS" }, "FilePath": "fill.frag" } } ] })";
  };
  auto fragment = [](const char* scale) {
    return std::string(
               "#version 450\nlayout(set = 0, binding = 0) uniform sampler2D tex;\n"
               "layout(location = 0) out vec4 o;\nvoid main() { o = texture(tex, vec2(0.5)) * ") +
           scale + "; }\n";
  };
  project.write("states.json", states("RGBA8_UNORM"));
  project.write("fill.vert", "#version 450\nvoid main() { gl_Position = vec4(0.0, 0.0, 0.0, 1.0); }\n");
  project.write("fill.frag", fragment("1.0"));
  project.pack();
  Dearchiver d = dearchiver_for(project);
  auto pso = d.unpack_graphics("Textured PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  const BindingInfo* tex = (*pso)->find_binding("tex");
  ASSERT_NE(tex, nullptr);
  const VkSampler sampler = tex->immutable_sampler;
  ASSERT_NE(sampler, VK_NULL_HANDLE);
  const VkPipeline before = (*pso)->pipeline;

  project.write("fill.frag", fragment("0.5"));
  project.pack();
  auto report = d.reload(project.load());
  ASSERT_TRUE(report) << report.error().message;
  ASSERT_TRUE(report->ok()) << report->failures[0].error.message;
  EXPECT_EQ(report->recreated, std::vector<std::string>{"Textured PSO"});
  EXPECT_NE((*pso)->pipeline, before);
  EXPECT_EQ((*pso)->find_binding("tex"), tex);  // the same BindingInfo, still valid
  EXPECT_EQ(tex->immutable_sampler, sampler);   // the same sampler object, found by content

  project.write("states.json", states("RGBA16_FLOAT"));
  project.pack();
  auto refused = d.reload(project.load());
  ASSERT_TRUE(refused) << refused.error().message;
  ASSERT_EQ(refused->failures.size(), 1u);
  EXPECT_EQ(refused->failures[0].error.code, ErrorCode::layout_changed);
  EXPECT_NE(refused->failures[0].error.message.find(
                "color target 0 changed from VK_FORMAT_R8G8B8A8_UNORM to VK_FORMAT_R16G16B16A16_SFLOAT"),
            std::string::npos)
      << refused->failures[0].error.message;
}

// A variant released before a reload that changes its archived state, then made again with the same
// callback: recorded as the callback made it (kBase = 0), not as the reload followed it (the new build's
// kBase = 9 with "no change").
TEST_F(ReloadTest, AVariantMadeAgainAfterAReloadIsRecordedAsItsCallbackMadeIt) {
  Project project = writers("variant_again", "kBase", "0u");
  Dearchiver d = dearchiver_for(project);
  auto zero = [](PatchableState& s) { EXPECT_TRUE(s.set_constant("kBase", 0u)); };  // as archived: no change
  const UnpackedPipeline* a = compute(d, "A", zero);
  ASSERT_TRUE(a);
  ASSERT_TRUE(d.release(a));
  std::string nine = two_writers();
  nine.replace(nine.find("\"Value\": 0"), 10, "\"Value\": 9");
  project.write("states.json", nine);
  project.pack();
  ASSERT_TRUE(d.reload(project.load()));
  a = compute(d, "A", zero);
  ASSERT_TRUE(a);
  EXPECT_EQ(run(*a), 0u);
  bool recorded = false;
  for (const auto& v : d.variants()) recorded = recorded || v.state.find("\"kBase\":0") != std::string::npos;
  EXPECT_TRUE(recorded) << "variants() lost the callback's kBase = 0";
  // And the next reload re-creates it with kBase = 0, as the callback set it.
  project.write("a.comp", writer_shader("kBase + 100u"));
  project.pack();
  auto again = d.reload(project.load());
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(run(*a), 100u);
}

// ArchiveFileWatch: only a complete archive with new bytes is handed back.
TEST_F(ReloadTest, TheFileWatchHandsBackOnlyCompleteNewArchives) {
  Project project = writers("watch", "1u", "2u");
  auto watch = ArchiveFileWatch::create(project.archive_path());
  ASSERT_TRUE(watch) << watch.error().message;
  auto nothing = watch->poll();
  ASSERT_TRUE(nothing);
  EXPECT_FALSE(*nothing);

  const std::string first = statepack::testing::read_file(project.archive_path());
  project.write("a.comp", writer_shader("3u"));
  const fs::path built = project.dir() / "next.spk";
  CommandResult r = run_command(project.pack_command("", built));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string second = statepack::testing::read_file(built);
  ASSERT_NE(first, second);

  // Half of the new archive written in place: never handed back, not an error.
  project.write("out.spk", second.substr(0, second.size() / 2));
  auto half = watch->poll();
  ASSERT_TRUE(half) << half.error().message;
  EXPECT_FALSE(*half);
  // The rest: handed back once.
  project.write("out.spk", second);
  auto whole = watch->poll();
  ASSERT_TRUE(whole) << whole.error().message;
  ASSERT_TRUE(*whole);
  auto again = watch->poll();
  ASSERT_TRUE(again);
  EXPECT_FALSE(*again);
  // The same bytes written again (a repack that changed nothing): nothing new.
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  project.write("out.spk", second);
  auto same = watch->poll();
  ASSERT_TRUE(same);
  EXPECT_FALSE(*same);
  // An error naming `needle` once, then nothing until the file changes.
  auto error_once = [&](const char* needle) {
    auto failed = watch->poll();
    ASSERT_FALSE(failed);
    EXPECT_NE(failed.error().message.find(needle), std::string::npos) << failed.error().message;
    auto quiet = watch->poll();
    ASSERT_TRUE(quiet);
    EXPECT_FALSE(*quiet);
  };
  // Not an archive.
  project.write("out.spk", std::string(256, 'x'));
  ASSERT_NO_FATAL_FAILURE(error_once("out.spk"));
  // Deleted: nothing; restored by rename: the archive.
  fs::remove(project.archive_path());
  auto missing = watch->poll();
  ASSERT_TRUE(missing);
  EXPECT_FALSE(*missing);
  fs::rename(built, project.archive_path());
  auto restored = watch->poll();
  ASSERT_TRUE(restored) << restored.error().message;
  EXPECT_FALSE(*restored);  // the bytes it handed back last: nothing new for the application
  project.write("out.spk", first);
  auto older = watch->poll();
  ASSERT_TRUE(older) << older.error().message;
  ASSERT_TRUE(*older);  // other bytes than the last handed back
  EXPECT_EQ((*older)->content_version(), 0u);
  // A directory where the archive was.
  fs::remove(project.archive_path());
  fs::create_directory(project.archive_path());
  ASSERT_NO_FATAL_FAILURE(error_once("directory"));
}

}  // namespace
}  // namespace statepack::testing

#ifdef STATEPACK_UNPACK_DEMO
namespace statepack::testing {
namespace {

// unpack_demo --watch, as a user runs it beside `statepack pack --watch`: one line per reload naming the
// pipelines re-created and kept, and a clean end on Ctrl-C with no validation message.
TEST(UnpackDemoWatch, PrintsOneLinePerReloadNamingWhatWasRecreatedAndKept) {
  Project project = writers("demo_watch", "1u", "2u");
  const std::string log = (project.dir() / "demo.log").string();
  const std::string wait_for =
      "for i in $(seq 100); do grep -q \"$1\" '" + log + "' && break; sleep 0.1; done";
  auto pack = [&](const std::string& a) {
    project.write("a.comp", writer_shader(a));
    return project.pack_command() + " >/dev/null";
  };
  std::string script = "waitfor() { " + wait_for + "; }\n'" STATEPACK_UNPACK_DEMO "' --watch '" +
                       project.archive_path().string() + "' >'" + log + "' 2>&1 & pid=$!\nwaitfor watching\n";
  script += pack("5u") + "\nwaitfor 'reload 1'\n";
  CommandResult r = run_command(script + "kill -INT $pid; wait $pid; echo exit=$?; cat '" + log + "'");
  EXPECT_NE(r.output.find("reload 1: re-created 1 ['A'], kept 1 ['B']"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("exit=0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("0 validation message(s)"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace statepack::testing
#endif
