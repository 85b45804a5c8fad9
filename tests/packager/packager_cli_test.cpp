// The statepack CLI as users run it: exit codes, error messages that name the file and place,
// atomic output, deterministic archives and the depfile.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "common/run_command.hpp"
#include "common/text_files.hpp"

namespace {

namespace fs = std::filesystem;

using CliRun = statepack::testing::CommandResult;

CliRun statepack(const std::string& args) {
  return statepack::testing::run_command(std::string("'") + STATEPACK_EXE + "' " + args);
}

// Runs statepack in `dir`, so that file names in its messages are relative to it.
CliRun statepack_in(const fs::path& dir, const std::string& args) {
  return statepack::testing::run_command("cd '" + dir.string() + "' && '" + STATEPACK_EXE + "' " + args);
}

using statepack::testing::read_file;

class PackagerCli : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = statepack::testing::fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "cli"); }
  std::string data(const std::string& name) const {
    return std::string(STATEPACK_TEST_DATA_DIR) + "/" + name;
  }
  std::string pack_args(const std::string& input, const fs::path& output,
                        const std::string& shader_dir = STATEPACK_SHADER_DIR) const {
    return "pack -i '" + input + "' -s '" + shader_dir + "' -o '" + output.string() + "' --vulkan";
  }
  fs::path dir_;
};

TEST_F(PackagerCli, HelpAndVersionSucceed) {
  CliRun help = statepack("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("pack"), std::string::npos);
  CliRun pack_help = statepack("pack --help");
  EXPECT_EQ(pack_help.exit_code, 0);
  EXPECT_NE(pack_help.output.find("--shader_dir"), std::string::npos);
  EXPECT_NE(pack_help.output.find("--depfile"), std::string::npos);
  CliRun version = statepack("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find("statepack"), std::string::npos);
}

TEST_F(PackagerCli, OneVersionNumberEverywhere) {
  // CMake's project version, --version and the producer version written into archives agree.
  const std::string version = STATEPACK_PROJECT_VERSION;
  CliRun run = statepack("--version");
  EXPECT_EQ(run.output.substr(0, run.output.find(' ', 10)), "statepack " + version) << run.output;
  fs::path out = dir_ / "slice.spk";
  ASSERT_EQ(statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", out)).exit_code, 0);
  CliRun inspect = statepack("inspect '" + out.string() + "'");
  EXPECT_NE(inspect.output.find("made by statepack " + version + ","), std::string::npos) << inspect.output;
  // CHANGELOG.md's newest entry is this version, and says what breaks and how to migrate.
  const std::string changelog = read_file(STATEPACK_CHANGELOG);
  const size_t newest = changelog.find("\n## ");
  ASSERT_NE(newest, std::string::npos) << "CHANGELOG.md has no release heading";
  EXPECT_EQ(changelog.substr(newest + 4, version.size() + 1), version + " ")
      << "CHANGELOG.md's newest entry is not statepack " << version << ": "
      << changelog.substr(newest + 1, changelog.find('\n', newest + 1) - newest - 1);
  const std::string entry = changelog.substr(newest, changelog.find("\n## ", newest + 1) - newest);
  // A minor release (x.y.0) says what breaks and how to migrate; a patch release breaks nothing.
  if (version.ends_with(".0")) {
    EXPECT_NE(entry.find("### Breaking changes"), std::string::npos);
    EXPECT_NE(entry.find("Migration"), std::string::npos);
  } else {
    EXPECT_EQ(entry.find("### Breaking changes"), std::string::npos)
        << "a patch release (" << version << ") with breaking changes: make it the next minor release";
  }
}

TEST_F(PackagerCli, PacksTheSliceWithDiligentStyleCommandLine) {
  fs::path out = dir_ / "slice.spk";
  // No subcommand, Diligent's flags: still a pack; foreign backends only warn.
  CliRun run =
      statepack("-i '" + std::string(STATEPACK_STATES_DIR) + "/slice.json' -s '" + STATEPACK_SHADER_DIR +
                "' -o '" + out.string() + "' --vulkan --dx12 --print_contents");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("warning: --dx12"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("'Gradient PSO' (graphics)"), std::string::npos) << run.output;
  EXPECT_TRUE(fs::exists(out));
}

TEST_F(PackagerCli, NoBackendIsAUsageError) {
  CliRun run = statepack("pack -i '" + std::string(STATEPACK_STATES_DIR) + "/slice.json' -o '" +
                         (dir_ / "x.spk").string() + "'");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--vulkan"), std::string::npos) << run.output;
  CliRun missing_output = statepack("pack -i x.json --vulkan");
  EXPECT_EQ(missing_output.exit_code, 2) << missing_output.output;
}

TEST_F(PackagerCli, ArchivesAreByteForByteDeterministic) {
  std::string input = std::string(STATEPACK_STATES_DIR) + "/slice.json";
  ASSERT_EQ(statepack(pack_args(input, dir_ / "a.spk")).exit_code, 0);
  ASSERT_EQ(statepack(pack_args(input, dir_ / "b.spk") + " -t 1").exit_code, 0);
  std::string a = read_file(dir_ / "a.spk"), b = read_file(dir_ / "b.spk");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

// A pack asks for its heaps on huge pages in-process (cli/huge_pages.hpp): where the kernel offers huge
// pages at all, the main heap and at least one thread heap are advised (the count drops when glibc's
// heaps are no longer found in /proc/self/maps), none when GLIBC_TUNABLES names hugetlb (the user's
// choice, kept) or in a sanitizer build; the archive is the same bytes either way, and what settling the
// options says is printed once.
TEST_F(PackagerCli, HugePagesChangeNothingButSpeed) {
  const std::string args = pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", dir_ / "%s.spk") +
                           " --dx11 -t 2 --time-report";
  auto run = [&](const std::string& environment, const std::string& name) {
    std::string a = args;
    a.replace(a.find("%s"), 2, name);
    return statepack::testing::run_command("env " + environment + " '" + STATEPACK_EXE + "' " + a);
  };
  // How many heaps the run says it advised; -1 when it does not say.
  auto advised_heaps = [](const std::string& output) {
    const std::string said = "heaps on huge pages (";
    const size_t at = output.find(said);
    return at == std::string::npos ? -1 : std::atoi(output.c_str() + at + said.size());
  };
  const CliRun advised = run("-u GLIBC_TUNABLES -u LD_PRELOAD -u MALLOC_ARENA_MAX", "advised");
  const CliRun kept = run("GLIBC_TUNABLES=glibc.malloc.hugetlb=0", "kept");
  std::ifstream modes_file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(modes_file, modes);
#if defined(__SANITIZE_ADDRESS__)
  const bool sanitized = true;  // (the program is built the same way, with the sanitizer's allocator)
#else
  const bool sanitized = false;
#endif
  if (!modes.empty() && modes.find("[never]") == std::string::npos && !sanitized)
    EXPECT_GE(advised_heaps(advised.output), 2) << modes << '\n' << advised.output;
  else
    EXPECT_EQ(advised_heaps(advised.output), 0) << modes << '\n' << advised.output;
  EXPECT_EQ(advised_heaps(kept.output), 0) << kept.output;
  for (const CliRun* r : {&advised, &kept}) {
    EXPECT_EQ(r->exit_code, 0) << r->output;
    const size_t warning = r->output.find("--dx11");
    EXPECT_NE(warning, std::string::npos) << r->output;
    EXPECT_EQ(r->output.find("--dx11", warning + 1), std::string::npos) << "printed twice:\n" << r->output;
  }
  EXPECT_EQ(read_file(dir_ / "advised.spk"), read_file(dir_ / "kept.spk"));
}

TEST_F(PackagerCli, DepfileListsEveryFileRead) {
  fs::path out = dir_ / "slice.spk";
  CliRun run = statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", out) + " --depfile '" +
                         (dir_ / "slice.d").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::string depfile = read_file(dir_ / "slice.d");
  EXPECT_EQ(depfile.rfind(out.string() + ":", 0), 0u) << depfile;
  for (const char* file : {"slice.json", "fill_buffer.comp", "fullscreen_triangle.vert", "gradient.frag",
                           "color_ramp.glsl" /* an #include */})
    EXPECT_NE(depfile.find(file), std::string::npos) << file << " missing from\n" << depfile;
}

TEST_F(PackagerCli, BadJsonNamesFileLineAndColumn) {
  CliRun run = statepack(pack_args(data("bad_json.json"), dir_ / "out.spk"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("bad_json.json:6:5: error: invalid JSON"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir_ / "out.spk"));
}

TEST_F(PackagerCli, MissingShaderFileIsReportedWithPointer) {
  CliRun run = statepack(pack_args(data("missing_shader.json"), dir_ / "out.spk"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("missing_shader.json:5:"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("'does_not_exist.comp' not found"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("[/Pipelines/0/pCS/FilePath]"), std::string::npos) << run.output;
}

TEST_F(PackagerCli, GlslErrorPointsIntoTheShaderFile) {
  CliRun run = statepack(pack_args(data("compile_error.json"), dir_ / "out.spk"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("compile_error.comp:5: error: shader 'Broken CS'"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("undefined_variable"), std::string::npos) << run.output;
}

// A Macros entry that breaks the text statepack puts before the shader (glslang's "-1:N") is reported at
// that entry: the notation's file, line, column and JSON pointer.
TEST_F(PackagerCli, AMacroThatBreaksTheTextBeforeTheShaderIsReportedAtItsEntry) {
  const fs::path json = dir_ / "macros.json";
  std::ofstream(json) << R"({"Pipelines": [
 {"PSODesc": {"Name": "P"}, "pCS": {"Desc": {"Name": "CS", "ShaderType": "COMPUTE"}, "SourceLanguage": "GLSL",
   "Source": "#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n",
   "Macros": [{"Name": "VARIANT", "Definition": "1"},
              {"Name": "X(", "Definition": "2"}]}}]})";
  CliRun run = statepack(pack_args(json.string(), dir_ / "out.spk"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("macros.json:5:15: error: shader 'CS': '#define' : bad argument (in the Macros "
                            "entry 'X(', which statepack puts before the shader's first line) "
                            "[/Pipelines/0/pCS/Macros/1]"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("-1:"), std::string::npos) << run.output;
}

TEST_F(PackagerCli, UnknownKeysAndEnumsGetSuggestionsAndAllAreReported) {
  CliRun run = statepack(pack_args(data("unknown_keys.json"), dir_ / "out.spk"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find(
                "unknown_keys.json:6:9: error: unknown GraphicsPipeline key 'PrimitiveTopolgy' (did you "
                "mean 'PrimitiveTopology'?)"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("unknown texture format 'RGBA8_UNROM' (did you mean 'RGBA8_UNORM'"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("2 error(s)"), std::string::npos) << run.output;
}

TEST_F(PackagerCli, FailedPackKeepsThePreviousArchive) {
  fs::path out = dir_ / "keep.spk";
  ASSERT_EQ(statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", out)).exit_code, 0);
  std::string before = read_file(out);
  EXPECT_EQ(statepack(pack_args(data("compile_error.json"), out)).exit_code, 1);
  EXPECT_EQ(read_file(out), before);
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << "left behind " << entry.path();
}

TEST_F(PackagerCli, UnwritableOutputIsAnIoError) {
  CliRun run =
      statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", "/nonexistent-dir/out.spk"));
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_NE(run.output.find("/nonexistent-dir/out.spk"), std::string::npos) << run.output;
}

}  // namespace

namespace {

class PackagerOptions : public PackagerCli {};

TEST_F(PackagerOptions, DumpDirHoldsSpirvAndDisassemblyPerPipeline) {
  fs::path dump = dir_ / "dump";
  CliRun run = statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", dir_ / "a.spk") +
                         " -d '" + dump.string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  fs::path spv = dump / "Vulkan" / "compute" / "Fill Buffer PSO" / "Fill Buffer CS.spv";
  fs::path text = dump / "Vulkan" / "graphics" / "Gradient PSO" / "Gradient PS.spvasm";
  ASSERT_TRUE(fs::exists(spv)) << spv;
  std::string words = read_file(spv);
  ASSERT_GE(words.size(), 20u);
  EXPECT_EQ(static_cast<uint8_t>(words[0]), 0x03);  // SPIR-V magic 0x07230203, little-endian
  EXPECT_EQ(static_cast<uint8_t>(words[3]), 0x07);
  EXPECT_NE(read_file(text).find("OpEntryPoint Fragment"), std::string::npos);
}

TEST_F(PackagerOptions, StripAndOptimizeShrinkTheArchiveAndKeepBindingNames) {
  std::string input = std::string(STATEPACK_STATES_DIR) + "/slice.json";
  ASSERT_EQ(statepack(pack_args(input, dir_ / "plain.spk")).exit_code, 0);
  CliRun stripped = statepack(pack_args(input, dir_ / "small.spk") + " --strip_debug --optimize size");
  ASSERT_EQ(stripped.exit_code, 0) << stripped.output;
  EXPECT_LT(fs::file_size(dir_ / "small.spk"), fs::file_size(dir_ / "plain.spk"));
  CliRun inspect = statepack("inspect --json '" + (dir_ / "small.spk").string() + "'");
  ASSERT_EQ(inspect.exit_code, 0) << inspect.output;
  EXPECT_NE(inspect.output.find("\"name\": \"Values\""), std::string::npos)
      << "binding names must survive stripping";
  EXPECT_EQ(statepack(pack_args(input, dir_ / "x.spk") + " --optimize fast").exit_code, 2);
}

TEST_F(PackagerOptions, InspectReportsDamageAndMissingFiles) {
  std::string input = std::string(STATEPACK_STATES_DIR) + "/slice.json";
  ASSERT_EQ(statepack(pack_args(input, dir_ / "a.spk")).exit_code, 0);
  CliRun text = statepack("inspect '" + (dir_ / "a.spk").string() + "'");
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.output.find("pipeline 'Gradient PSO' (graphics)"), std::string::npos) << text.output;
  std::string bytes = read_file(dir_ / "a.spk");
  bytes[bytes.size() / 2] ^= 0x40;
  std::ofstream(dir_ / "damaged.spk", std::ios::binary) << bytes;
  CliRun damaged = statepack("inspect '" + (dir_ / "damaged.spk").string() + "'");
  EXPECT_EQ(damaged.exit_code, 1);
  EXPECT_NE(damaged.output.find("checksum mismatch"), std::string::npos) << damaged.output;
  EXPECT_EQ(statepack("inspect '" + (dir_ / "none.spk").string() + "'").exit_code, 3);
}

TEST_F(PackagerOptions, DepfileFollowsImportsAndHlslIncludes) {
  fs::path out = dir_ / "c.spk";
  std::string corpus = std::string(STATEPACK_CORPUS_DIR);
  CliRun run = statepack("pack -i '" + corpus + "/valid/imports_and_defaults.json' -i '" + corpus +
                         "/valid/diligent_style.json' -s '" + corpus + "/shaders' -o '" + out.string() +
                         "' --vulkan --depfile '" + (dir_ / "c.d").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::string depfile = read_file(dir_ / "c.d");
  for (const char* file : {"common/defaults.json", "tri.vert", "shade.hlsl", "shade_common.hlsli"})
    EXPECT_NE(depfile.find(file), std::string::npos) << file << " missing from\n" << depfile;
}

}  // namespace

namespace {

class Verify : public PackagerCli {};

// verify's report without the creation times it prints (": created in 0.31 ms (...)" after an object,
// "; 2 pipelines created in ..." after a count), which differ from run to run.
std::string without_times(const std::string& report) {
  static const std::regex times(R"((: created in |; [0-9]+ pipelines? created in )[^\n]*)");
  return std::regex_replace(report, times, "");
}

TEST_F(Verify, ReportsEveryObjectAndWarmsACache) {
  fs::path out = dir_ / "slice.spk", cache = dir_ / "cache.bin";
  ASSERT_EQ(statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", out)).exit_code, 0);
  CliRun timed = statepack("verify '" + out.string() + "' --cache '" + cache.string() + "'");
  // Each pipeline with its creation time and the driver's own (lavapipe has creation feedback), and a total.
  static const std::regex pipeline_line(
      R"(ok     compute pipeline 'Fill Buffer PSO': created in [0-9]+\.[0-9]{2} ms \(the driver's feedback: )"
      R"([0-9]+\.[0-9]{2} ms\)\n)");
  EXPECT_TRUE(std::regex_search(timed.output, pipeline_line)) << timed.output;
  static const std::regex total_line(
      R"(slice\.spk: 2 of 2 objects ok; 2 pipelines created in [0-9.]+ ms \(the driver's feedback: [0-9.]+ ms, )"
      R"(0 from the pipeline cache\)\n)");
  EXPECT_TRUE(std::regex_search(timed.output, total_line)) << timed.output;
  CliRun run{timed.exit_code, without_times(timed.output)};
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("validation layer on"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("ok     compute pipeline 'Fill Buffer PSO'\n"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("ok     graphics pipeline 'Gradient PSO'\n"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("slice.spk: 2 of 2 objects ok\n"), std::string::npos) << run.output;
  EXPECT_TRUE(fs::exists(cache));
  // The cache written is accepted on the same device (its header matches).
  CliRun again = statepack("verify '" + out.string() + "' --cache '" + cache.string() + "'");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(again.output.find("starting empty"), std::string::npos) << again.output;
}

TEST_F(Verify, RunTimeFormatsAreVerifiedWithTheFormatGiven) {
  fs::path json = dir_ / "unknown.json", out = dir_ / "unknown.spk";
  std::ofstream(json) << R"({"Pipelines": [{"PSODesc": {"Name": "Swapchain PSO"},
    "GraphicsPipeline": {"NumRenderTargets": 1, "RTVFormats": {"0": "UNKNOWN"}, "DepthStencilDesc": {"DepthEnable": false}},
    "pVS": {"Desc": {"Name": "VS", "ShaderType": "VERTEX"}, "FilePath": "fullscreen_triangle.vert"},
    "pPS": {"Desc": {"Name": "PS", "ShaderType": "PIXEL"}, "FilePath": "gradient.frag"}}]})";
  ASSERT_EQ(statepack(pack_args(json.string(), out)).exit_code, 0);
  CliRun bgra = statepack("verify --format BGRA8_UNORM_SRGB '" + out.string() + "'");
  bgra.output = without_times(bgra.output);
  EXPECT_EQ(bgra.exit_code, 0) << bgra.output;
  // The slots the application must set are shown, with the format they were verified with.
  EXPECT_NE(bgra.output.find("ok     graphics pipeline 'Swapchain PSO' (render target 0, set at run "
                             "time: verified as BGRA8_UNORM_SRGB)\n"),
            std::string::npos)
      << bgra.output;
  // A depth format as a color target cannot be created: the object fails, and so does the run.
  CliRun depth = statepack("verify --format D32_FLOAT '" + out.string() + "'");
  EXPECT_EQ(depth.exit_code, 1) << depth.output;
  EXPECT_NE(depth.output.find("FAILED graphics pipeline 'Swapchain PSO' (render target 0, set at run time: "
                              "verified as D32_FLOAT): "),
            std::string::npos)
      << depth.output;
  EXPECT_EQ(statepack("verify --format NOT_A_FORMAT '" + out.string() + "'").exit_code, 2);
}

// verify's device has every core feature of Vulkan 1.0 to 1.3 the device supports on: a multiview
// pipeline (the MultiView capability) and one reading through buffer device addresses
// (PhysicalStorageBufferAddresses) are valid, and verify says so rather than blame the archive.
TEST_F(Verify, PipelinesNeedingVulkan11To13FeaturesAreVerified) {
  fs::path json = dir_ / "features.json", out = dir_ / "features.spk";
  std::ofstream(json) << R"({"Pipelines": [
    {"PSODesc": {"Name": "Per View PSO"}, "GraphicsPipeline": {"RTVFormats": {"0": "RGBA8_UNORM"}},
     "pVS": {"Desc": {"Name": "Per View VS", "ShaderType": "VERTEX"}, "SourceLanguage": "GLSL",
             "Source": "#version 450\n#extension GL_EXT_multiview : require\nlayout(location = 0) out vec4 color;\nvoid main() { color = vec4(float(gl_ViewIndex), 0.0, 0.0, 1.0); gl_Position = vec4(0.0, 0.0, 0.0, 1.0); }\n"},
     "pPS": {"Desc": {"Name": "Color PS", "ShaderType": "PIXEL"}, "SourceLanguage": "GLSL",
             "Source": "#version 450\nlayout(location = 0) in vec4 color;\nlayout(location = 0) out vec4 target;\nvoid main() { target = color; }\n"}},
    {"PSODesc": {"Name": "Pointer Chase PSO"},
     "pCS": {"Desc": {"Name": "Pointer Chase CS", "ShaderType": "COMPUTE"}, "SourceLanguage": "GLSL",
             "Source": "#version 450\n#extension GL_EXT_buffer_reference : require\nlayout(local_size_x = 64) in;\nlayout(buffer_reference, std430) buffer Values { uint v[]; };\nlayout(push_constant) uniform Args { Values values; } args;\nvoid main() { args.values.v[gl_GlobalInvocationID.x] = gl_GlobalInvocationID.x; }\n"}}]})";
  ASSERT_EQ(statepack(pack_args(json.string(), out)).exit_code, 0);
  CliRun run = statepack("verify '" + out.string() + "'");
  run.output = without_times(run.output);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("ok     graphics pipeline 'Per View PSO'\n"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("ok     compute pipeline 'Pointer Chase PSO'\n"), std::string::npos)
      << run.output;
}

// Objects are created in worker processes: a driver that crashes or hangs inside pipeline creation
// (the test layer tests/fault_layer/ does either for an entry point so named) fails that object only,
// with the reason, and verify goes on with the next object and the next archive.
TEST_F(Verify, DriverCrashesAndHangsFailTheirObjectAndVerifyGoesOn) {
  fs::path json = dir_ / "faults.json", out = dir_ / "faults.spk", slice = dir_ / "slice.spk";
  auto pipeline = [](const std::string& name, const std::string& entry) {
    return R"({"PSODesc": {"Name": ")" + name + R"("}, "pCS": {"Desc": {"Name": ")" + name +
           R"( CS", "ShaderType": "COMPUTE"}, "SourceLanguage": "HLSL", "EntryPoint": ")" + entry +
           R"(", "Source": "RWStructuredBuffer<uint> data;\n[numthreads(1, 1, 1)] void )" + entry +
           R"(() { data[0] = 1; }\n"}})";
  };
  std::ofstream(json) << "{\"Pipelines\": [" << pipeline("A First", "Fill") << ","
                      << pipeline("B Crashes", "CrashTheDriver") << "," << pipeline("C Between", "Fill")
                      << "," << pipeline("D Hangs", "HangTheDriver") << ","
                      << pipeline("E Crashes Last", "CrashTheDriver") << "]}";
  ASSERT_EQ(statepack(pack_args(json.string(), out)).exit_code, 0);
  ASSERT_EQ(statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", slice)).exit_code, 0);
  const std::string faults = std::string("XDG_DATA_DIRS='") + STATEPACK_FAULT_LAYER_DIR +
                             ":/usr/local/share:/usr/share' STATEPACK_TEST_FAULTS=1 ";
  CliRun run = statepack::testing::run_command(faults + "'" + STATEPACK_EXE + "' verify --timeout 2 '" +
                                               out.string() + "' '" + slice.string() + "'");
  run.output = without_times(run.output);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  const std::string expected =
      "ok     compute pipeline 'A First'\n"
      "FAILED compute pipeline 'B Crashes': the driver crashed (SIGSEGV: Segmentation fault) while creating "
      "it; verify went on in a new process\n"
      "ok     compute pipeline 'C Between'\n"
      "FAILED compute pipeline 'D Hangs': no answer within 2 s (--timeout): the driver hung while creating "
      "it; verify went on in a new process\n"
      "FAILED compute pipeline 'E Crashes Last': the driver crashed (SIGSEGV: Segmentation fault) while "
      "creating it; verify went on in a new process\n" +
      out.string() + ": 2 of 5 objects ok\n" +
      "ok     compute pipeline 'Fill Buffer PSO'\n"
      "ok     graphics pipeline 'Gradient PSO'\n" +
      slice.string() + ": 2 of 2 objects ok\n" + "in all: 4 of 7 objects ok\n";
  const size_t device_line = run.output.find('\n');
  EXPECT_EQ(run.output.substr(0, run.output.find(' ')), "device:") << run.output;
  EXPECT_EQ(run.output.substr(device_line + 1), expected);
  // Without the faults, the same archive's good objects verify, also in-process (--timeout 0).
  CliRun in_process = statepack("verify --timeout 0 '" + slice.string() + "'");
  in_process.output = without_times(in_process.output);
  EXPECT_EQ(in_process.exit_code, 0) << in_process.output;
  EXPECT_NE(in_process.output.find(slice.string() + ": 2 of 2 objects ok\n"), std::string::npos)
      << in_process.output;
}

// --variants creates exactly the variants a file lists (tests/runtime/variants_test.cpp writes one with
// the Dearchiver); a variant whose pipeline no archive has fails, and a damaged file is an input error.
TEST_F(Verify, VariantsFilesCreateExactlyTheirVariants) {
  fs::path out = dir_ / "slice.spk", variants = dir_ / "variants.json", cache = dir_ / "warm.cache";
  ASSERT_EQ(statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", out)).exit_code, 0);
  std::ofstream(variants) << R"({"statepack_variants": 1, "variants": [
    {"pipeline": "Gradient PSO", "kind": "graphics", "state": {"color_formats.0": "VK_FORMAT_B8G8R8A8_SRGB"}},
    {"pipeline": "Gradient PSO", "kind": "graphics", "state": {"color_formats.0": "VK_FORMAT_R16G16B16A16_SFLOAT",
     "blend.0.enable": true, "blend.0.src_color": "VK_BLEND_FACTOR_SRC_ALPHA"}},
    {"pipeline": "Gone PSO", "kind": "compute", "state": {}}]})";
  CliRun run = statepack("verify '" + out.string() + "' --variants '" + variants.string() + "' --cache '" +
                         cache.string() + "'");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  const std::string report = without_times(run.output);
  const std::string expected =
      "FAILED compute pipeline 'Gone PSO' as archived: variants file '" + variants.string() +
      "' at /variants/2/pipeline: no archive given has a pipeline named 'Gone PSO'\n"
      "ok     graphics pipeline 'Gradient PSO' with {\"color_formats.0\":\"VK_FORMAT_B8G8R8A8_SRGB\"}\n"
      "ok     graphics pipeline 'Gradient PSO' with {\"color_formats.0\":\"VK_FORMAT_R16G16B16A16_SFLOAT\","
      "\"blend.0.enable\":true,\"blend.0.src_color\":\"VK_BLEND_FACTOR_SRC_ALPHA\"}\n" +
      out.string() + ": 2 of 2 objects ok\n";
  EXPECT_NE(report.find(expected), std::string::npos) << report;
  EXPECT_NE(report.find("\nin all: 2 of 3 objects ok\n"), std::string::npos) << report;  // why exit 1
  EXPECT_EQ(report.find("Fill Buffer PSO"), std::string::npos) << report;  // exactly the variants
  EXPECT_TRUE(fs::exists(cache));

  std::ofstream(variants, std::ios::trunc)
      << R"({"statepack_variants": 1, "variants": [{"pipeline": "Gradient PSO", "kind": "graphics", "state": {"blend.9.enable": true}}]})";
  CliRun bad = statepack("verify '" + out.string() + "' --variants '" + variants.string() + "'");
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(
      bad.output.find("statepack: error: variants file '" + variants.string() +
                      "' at /variants/0/state/blend.9.enable: no such field (did you mean 'blend.0.enable'"),
      std::string::npos)
      << bad.output;
  CliRun missing =
      statepack("verify '" + out.string() + "' --variants '" + (dir_ / "none.json").string() + "'");
  EXPECT_EQ(missing.exit_code, 3) << missing.output;
}

// A bad entry of a variants file is named by the file and its JSON pointer, with a suggestion where a
// name is misspelt, never as "the modify callback" (the file is the party that set the values).
TEST_F(Verify, VariantsFileMistakesNameTheFileAndTheEntry) {
  fs::path out = dir_ / "slice.spk", variants = dir_ / "v.json";
  ASSERT_EQ(statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", out)).exit_code, 0);
  std::ofstream(variants) << R"({"statepack_variants": 1, "variants": [
    {"pipeline": "Gradient PSO", "kind": "graphics", "state": {"color_formats.0": "VK_FORMAT_R8G8B8A8_UINT"}},
    {"pipeline": "Gradient PS", "kind": "graphics", "state": {}},
    {"pipeline": "Fill Buffer PSO", "kind": "graphics", "state": {}}]})";
  CliRun run = statepack("verify '" + out.string() + "' --variants '" + variants.string() + "'");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  const std::string file = "variants file '" + variants.string() + "'";
  const std::string expected =
      "FAILED graphics pipeline 'Gradient PS' as archived: " + file +
      " at /variants/1/pipeline: no archive given has a pipeline named 'Gradient PS' (did you mean "
      "'Gradient PSO'?)\n"
      "FAILED graphics pipeline 'Gradient PSO' with {\"color_formats.0\":\"VK_FORMAT_R8G8B8A8_UINT\"}: " +
      file +
      " at /variants/0: pipeline 'Gradient PSO': render target 0 has format VK_FORMAT_R8G8B8A8_UINT (set by "
      "the variant), which holds unsigned integer values, but the shader's variable at location 0 is "
      "float\n"
      "FAILED graphics pipeline 'Fill Buffer PSO' as archived: " +
      file +
      " at /variants/2/kind: pipeline 'Fill Buffer PSO' is a compute pipeline, not a graphics pipeline\n" +
      out.string() + ": 0 of 2 objects ok\n" + "in all: 0 of 3 objects ok\n";
  EXPECT_NE(without_times(run.output).find(expected), std::string::npos) << run.output;

  std::ofstream(variants, std::ios::trunc) << R"({"statepack_variants": 1, "variants": [
    {"pipeline": "Gradient PSO", "kind": "graphics", "state": {"color_formats.0": "VK_FORMAT_R8G8B8A8_UNROM"}}]})";
  CliRun misspelt = statepack("verify '" + out.string() + "' --variants '" + variants.string() + "'");
  EXPECT_EQ(misspelt.exit_code, 1) << misspelt.output;
  EXPECT_NE(misspelt.output.find("statepack: error: " + file +
                                 " at /variants/0/state/color_formats.0: 'VK_FORMAT_R8G8B8A8_UNROM' is not a "
                                 "VkFormat name (did you mean 'VK_FORMAT_R8G8B8A8_UNORM'"),
            std::string::npos)
      << misspelt.output;
  EXPECT_EQ(misspelt.output.find("objects ok"), std::string::npos) << misspelt.output;
}

TEST_F(Verify, DamagedArchivesAndMissingDevicesAreErrors) {
  fs::path out = dir_ / "slice.spk";
  ASSERT_EQ(statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", out)).exit_code, 0);
  std::string bytes = read_file(out);
  bytes[bytes.size() / 2] ^= 0x5A;
  std::ofstream(out, std::ios::binary | std::ios::trunc) << bytes;
  CliRun damaged = statepack("verify '" + out.string() + "'");
  EXPECT_EQ(damaged.exit_code, 3) << damaged.output;
  EXPECT_NE(damaged.output.find("checksum mismatch"), std::string::npos) << damaged.output;
  CliRun device = statepack("verify --device 99 '" + out.string() + "'");
  EXPECT_EQ(device.exit_code, 3) << device.output;
  EXPECT_NE(device.output.find("cannot create a Vulkan device: there is no Vulkan device 99"),
            std::string::npos)
      << device.output;
}

}  // namespace

namespace {

TEST_F(PackagerCli, InspectShowsTheWholeGraphicsState) {
  fs::path out = dir_ / "full.spk";
  const std::string corpus = STATEPACK_CORPUS_DIR;
  CliRun pack = statepack(pack_args(corpus + "/valid/full_graphics_state.json", out, corpus + "/shaders"));
  ASSERT_EQ(pack.exit_code, 0) << pack.output;
  CliRun text = statepack("inspect '" + out.string() + "'");
  for (const char* line :
       {"    raster: SOLID, front face VK_FRONT_FACE_CLOCKWISE, depth clamp off, depth bias 2 (clamp 0.25, "
        "slope "
        "1.5)\n",
        "    depth: write on, compare LESS_EQUAL, format D24_UNORM_S8_UINT (VK_FORMAT_D24_UNORM_S8_UINT)\n",
        "    stencil: on, read mask 0xf, write mask 0xf0, front NOT_EQUAL fail KEEP pass REPLACE depth-fail "
        "INCR_SAT, back ALWAYS fail KEEP pass ZERO depth-fail KEEP\n",
        "    multisample: 1 sample(s), mask 0xffffffff, alpha to coverage off\n",
        "    target 0: blend on, color SRC_ALPHA ADD INV_SRC_ALPHA, alpha ONE MAX ZERO, write mask 0x7\n",
        "  attachment 1: D24_UNORM_S8_UINT (VK_FORMAT_D24_UNORM_S8_UINT) x1, CLEAR/STORE, stencil "
        "CLEAR/DISCARD, "
        "VK_IMAGE_LAYOUT_UNDEFINED -> VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL\n",
        "  dependency external -> 0: stages RENDER_TARGET -> EARLY_FRAGMENT_TESTS | RENDER_TARGET, access "
        "NONE -> "
        "RENDER_TARGET_WRITE | DEPTH_STENCIL_WRITE\n"})
    EXPECT_NE(text.output.find(line), std::string::npos) << line << "\nin:\n" << text.output;
  CliRun json = statepack("inspect --json '" + out.string() + "'");
  for (const char* field :
       {"\"slope\": 1.5", "\"write_mask\": 240", "\"depth_fail\": \"INCR_SAT\"",
        "\"sample_mask\": 4294967295", "\"dst_access\": \"RENDER_TARGET_WRITE | DEPTH_STENCIL_WRITE\"",
        "\"depth_stencil_format\": \"D24_UNORM_S8_UINT\",\n        \"vk_depth_stencil_format\": "
        "\"VK_FORMAT_D24_UNORM_S8_UINT\""})
    EXPECT_NE(json.output.find(field), std::string::npos) << field;
}

}  // namespace

namespace {

// A render pass whose color attachment some devices cannot render to packs with a warning at the
// attachment (lavapipe supports RGB32_FLOAT; Vulkan does not require it).
TEST_F(PackagerCli, RenderPassColorFormatsVulkanDoesNotGuaranteeAreWarnedAbout) {
  std::string notation = read_file(fs::path(STATEPACK_CORPUS_DIR) / "valid/render_pass.json");
  const std::string from = R"("Format": "RGBA8_UNORM")";
  ASSERT_NE(notation.find(from), std::string::npos);
  notation.replace(notation.find(from), from.size(), R"("Format": "RGB32_FLOAT")");
  fs::path json = dir_ / "render_pass.json", out = dir_ / "render_pass.spk";
  std::ofstream(json) << notation;
  CliRun run = statepack("pack -i '" + json.string() + "' -s '" + std::string(STATEPACK_CORPUS_DIR) +
                         "/shaders' -o '" + out.string() + "' --vulkan");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(
      run.output.find("render_pass.json:6:9: warning: render pass 'Main Pass': attachment 0 is RGB32_FLOAT, "
                      "used as a color attachment, which Vulkan does not require devices to support: some "
                      "devices will refuse this render pass [/RenderPasses/0/pAttachments/0]"),
      std::string::npos)
      << run.output;
}

TEST_F(PackagerCli, AnUnknownEnumWithNoNearMatchListsTheValidValues) {
  fs::path json = dir_ / "topology.json";
  std::ofstream(json)
      << R"({"Defaults": {"Pipeline": {"GraphicsPipeline": {"PrimitiveTopology": "QUADS"}}}})";
  CliRun run = statepack("pack --check --vulkan -i '" + json.string() + "'");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(
      run.output.find("error: unknown primitive topology 'QUADS' (valid: TRIANGLE_LIST, TRIANGLE_STRIP, "
                      "POINT_LIST, LINE_LIST, LINE_STRIP, TRIANGLE_LIST_ADJ, TRIANGLE_STRIP_ADJ, "
                      "LINE_LIST_ADJ, LINE_STRIP_ADJ, 1_CONTROL_POINT_PATCHLIST, "),
      std::string::npos)
      << run.output;
  // Long tables are cut after 20 names.
  std::ofstream(json) << R"({"Defaults": {"Pipeline": {"GraphicsPipeline": {"DSVFormat": "QQQQ"}}}})";
  CliRun formats = statepack("pack --check --vulkan -i '" + json.string() + "'");
  EXPECT_NE(formats.output.find(" more in docs/notation.md)"), std::string::npos) << formats.output;
}

}  // namespace

namespace {

// A -s or -r directory that is not there is one error naming it, not a "not found" per shader.
TEST_F(PackagerCli, AMissingSearchDirectoryIsReportedOnceItself) {
  std::ofstream(dir_ / "not_a_dir") << "x";
  const std::string corpus = STATEPACK_CORPUS_DIR;
  CliRun run =
      statepack_in(dir_, "pack --check --vulkan -i '" + corpus +
                             "/valid/standalone_and_compute.json' -s shaderz -s not_a_dir -s shaderz "
                             "-s '" +
                             corpus + "/shaders' -r states_dir");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_EQ(run.output,
            "statepack: error: -s 'shaderz': the directory does not exist\n"
            "statepack: error: -s 'not_a_dir': the directory is not a directory\n"
            "statepack: error: -r 'states_dir': the directory does not exist\n");
}

// One file, one name: the main notation file given by its absolute path is named like its imports,
// relative to the working directory when below it.
TEST_F(PackagerCli, FileNamesAreRelativeToTheWorkingDirectoryHoweverTheInputIsSpelt) {
  const fs::path invalid = fs::path(STATEPACK_CORPUS_DIR) / "invalid";
  for (const std::string& input : {(invalid / "defaults_typo.json").string(),
                                   std::string("defaults_typo.json"), std::string("./defaults_typo.json")}) {
    CliRun run = statepack_in(invalid, "pack --check --vulkan -i '" + input + "'");
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_EQ(run.output.rfind("defaults_typo.json:3:61: error: unknown RasterizerDesc key 'CulMode'", 0), 0u)
        << input << ":\n"
        << run.output;
  }
  // Imports are named the same way: the warning is in the imported file.
  const fs::path warnings = fs::path(STATEPACK_CORPUS_DIR) / "warnings";
  CliRun import = statepack_in(warnings.parent_path(), "pack --check --vulkan -i '" +
                                                           (warnings / "import_cycle_a.json").string() + "'");
  EXPECT_NE(import.output.find(
                "warnings/import_cycle_b.json:2:15: warning: import cycle: warnings/import_cycle_a.json "
                "-> warnings/import_cycle_b.json -> warnings/import_cycle_a.json"),
            std::string::npos)
      << import.output;
}

// HLSL push constants in glslang's spellings become the pipeline's push-constant range.
TEST_F(PackagerCli, HlslPushConstantsBecomeThePipelinesRange) {
  fs::path out = dir_ / "push.spk";
  const std::string corpus = STATEPACK_CORPUS_DIR;
  CliRun pack = statepack(pack_args(corpus + "/valid/hlsl_push_constants.json", out, corpus + "/shaders"));
  ASSERT_EQ(pack.exit_code, 0) << pack.output;
  CliRun json = statepack("inspect --json '" + out.string() + "'");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  // Two float4 for vertex and pixel stages; a uint and a float for the compute one.
  for (const char* range : {"\"push_constants\": {\n        \"size\": 32,\n        \"stages\": [\n          "
                            "\"VERTEX\",\n          \"PIXEL\"\n        ]",
                            "\"push_constants\": {\n        \"size\": 8,\n        \"stages\": [\n          "
                            "\"COMPUTE\"\n        ]"})
    EXPECT_NE(json.output.find(range), std::string::npos) << range << "\nin:\n" << json.output;
}

}  // namespace

namespace {

class Merge : public PackagerCli {
 protected:
  // A notation with one graphics pipeline 'name' drawing with `topology`, and the Fill Buffer compute
  // pipeline every archive here shares.
  fs::path notation(const std::string& file, const std::string& name, const std::string& topology) {
    fs::path json = dir_ / file;
    std::ofstream(json)
        << R"({"Pipelines": [{"PSODesc": {"Name": ")" << name << R"("},
      "GraphicsPipeline": {"PrimitiveTopology": ")"
        << topology << R"(", "RTVFormats": {"0": "RGBA8_UNORM"}, "DepthStencilDesc": {"DepthEnable": false}},
      "pVS": {"Desc": {"Name": "VS", "ShaderType": "VERTEX"}, "FilePath": "fullscreen_triangle.vert"},
      "pPS": {"Desc": {"Name": "PS", "ShaderType": "PIXEL"}, "FilePath": "gradient.frag"}},
      {"PSODesc": {"Name": "Fill Buffer PSO"},
       "pCS": {"Desc": {"Name": "Fill Buffer CS", "ShaderType": "COMPUTE"}, "FilePath": "fill_buffer.comp"}}]})";
    return json;
  }
  fs::path pack(const fs::path& json, const std::string& extra = "") {
    fs::path out = fs::path(json).replace_extension(".spk");
    CliRun run = statepack(pack_args(json.string(), out) + extra);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return out;
  }
  std::string pipelines_of(const fs::path& archive) {
    CliRun inspect = statepack("inspect --json '" + archive.string() + "'");
    EXPECT_EQ(inspect.exit_code, 0) << inspect.output;
    std::string names;
    for (size_t at = inspect.output.find("\"name\": \""); at != std::string::npos;
         at = inspect.output.find("\"name\": \"", at + 1))
      names += inspect.output.substr(at + 9, inspect.output.find('"', at + 9) - at - 9) + ";";
    return names;
  }
};

TEST_F(Merge, SharedObjectsAreStoredOnceAndTheBytesAreDeterministic) {
  fs::path a = pack(notation("a.json", "Lines PSO", "LINE_LIST"));
  fs::path b = pack(notation("b.json", "Strip PSO", "TRIANGLE_STRIP"));
  fs::path merged = dir_ / "merged.spk", again = dir_ / "again.spk", twice = dir_ / "twice.spk";
  CliRun run = statepack("merge -o '" + merged.string() + "' '" + a.string() + "' '" + b.string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // Both graphics pipelines, and the compute pipeline both define identically, once.
  std::string names = pipelines_of(merged);
  for (const char* name : {"Lines PSO", "Strip PSO", "Fill Buffer PSO", "Fill Buffer CS"})
    EXPECT_NE(names.find(name), std::string::npos) << name << " missing: " << names;
  EXPECT_EQ(names.find("Fill Buffer PSO"), names.rfind("Fill Buffer PSO")) << names;
  // Three shaders' SPIR-V is shared, so the merged archive is much smaller than the two together.
  EXPECT_NE(run.output.find("3 SPIR-V blob(s)"), std::string::npos) << run.output;
  EXPECT_LT(fs::file_size(merged), fs::file_size(a) + fs::file_size(b) - 1000);
  // Same inputs, same bytes; merging an input in again changes nothing.
  ASSERT_EQ(
      statepack("merge -o '" + again.string() + "' '" + a.string() + "' '" + b.string() + "'").exit_code, 0);
  EXPECT_EQ(read_file(merged), read_file(again));
  ASSERT_EQ(
      statepack("merge -o '" + twice.string() + "' '" + merged.string() + "' '" + b.string() + "'").exit_code,
      0);
  EXPECT_EQ(read_file(merged), read_file(twice));
  // And it works: every object unpacks on lavapipe with the validation layer on.
  CliRun verify = statepack("verify '" + merged.string() + "'");
  EXPECT_EQ(verify.exit_code, 0) << verify.output;
  EXPECT_NE(verify.output.find("3 of 3 objects ok"), std::string::npos) << verify.output;
}

TEST_F(Merge, ANameDefinedDifferentlyIsAnErrorNamingBothFiles) {
  fs::path a = pack(notation("a.json", "Shared PSO", "LINE_LIST"));
  fs::path b = pack(notation("b.json", "Shared PSO", "TRIANGLE_STRIP"));
  fs::path merged = dir_ / "merged.spk";
  CliRun run = statepack("merge -o '" + merged.string() + "' '" + a.string() + "' '" + b.string() + "'");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("error: pipeline 'Shared PSO' is defined differently in '" + a.string() +
                            "' and '" + b.string() + "'"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(fs::exists(merged));
  // Content versions must agree unless the merged one is given.
  fs::path c = pack(notation("c.json", "Other PSO", "LINE_LIST"), " -v 7");
  CliRun versions = statepack("merge -o '" + merged.string() + "' '" + a.string() + "' '" + c.string() + "'");
  EXPECT_EQ(versions.exit_code, 1);
  EXPECT_NE(
      versions.output.find("has content version 7, the archives before it 0: give the merged one with -v"),
      std::string::npos)
      << versions.output;
  EXPECT_EQ(statepack("merge -v 9 -o '" + merged.string() + "' '" + a.string() + "' '" + c.string() + "'")
                .exit_code,
            0);
  // The output never replaces an input.
  CliRun onto = statepack("merge -o '" + a.string() + "' '" + a.string() + "' '" + c.string() + "'");
  EXPECT_EQ(onto.exit_code, 2) << onto.output;
  EXPECT_NE(onto.output.find("statepack never replaces its inputs"), std::string::npos) << onto.output;
}

}  // namespace

namespace {

// --opengl: the slice's shaders compiled again for OpenGL (one source, #ifdef VULKAN), each pipeline with
// a per-kind binding table; alone or beside Vulkan.
TEST_F(PackagerCli, OpenGlBackendHasItsOwnModulesAndBindingTable) {
  const std::string input = std::string(STATEPACK_STATES_DIR) + "/slice.json";
  const fs::path both = dir_ / "both.spk", gl_only = dir_ / "gl.spk";
  CliRun pack = statepack("pack -i '" + input + "' -s '" + STATEPACK_SHADER_DIR + "' -o '" + both.string() +
                          "' --vulkan --opengl");
  ASSERT_EQ(pack.exit_code, 0) << pack.output;
  CliRun json = statepack("inspect --json '" + both.string() + "'");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  for (const char* field : {"\"backends\": [\n    \"vulkan\",\n    \"opengl\"\n  ]", "\"opengl_pipelines\"",
                            "\"kind\": \"uniform buffer\"", "\"name\": \"Params\"",
                            "\"kind\": \"storage buffer\"", "\"name\": \"Values\""})
    EXPECT_NE(json.output.find(field), std::string::npos) << field << "\n" << json.output;
  CliRun text = statepack("inspect '" + both.string() + "'");
  for (const char* line :
       {"OpenGL pipeline 'Fill Buffer PSO' (compute)\n", "  uniform buffer 0: 'Params' x1 [\"COMPUTE\"]\n",
        "  storage buffer 0: 'Values' x1 [\"COMPUTE\"]\n", "OpenGL pipeline 'Gradient PSO' (graphics)\n"})
    EXPECT_NE(text.output.find(line), std::string::npos) << line << "\nin:\n" << text.output;
  // The Vulkan part is what --vulkan alone writes: the same pipelines, push constants and all.
  EXPECT_NE(text.output.find("  push constants: 12 bytes\n"), std::string::npos) << text.output;

  CliRun alone = statepack("pack -i '" + input + "' -s '" + STATEPACK_SHADER_DIR + "' -o '" +
                           gl_only.string() + "' --opengl");
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  CliRun gl_text = statepack("inspect '" + gl_only.string() + "'");
  EXPECT_NE(gl_text.output.find("backends: [\"opengl\"]"), std::string::npos) << gl_text.output;
  EXPECT_EQ(gl_text.output.find("\npipeline '"), std::string::npos) << "no Vulkan pipelines:\n"
                                                                    << gl_text.output;
  EXPECT_NE(gl_text.output.find("OpenGL pipeline 'Gradient PSO'"), std::string::npos) << gl_text.output;
}

// What OpenGL cannot express is an error naming the shader or resource, once per problem: Vulkan-only
// GLSL (push constants, gl_VertexIndex), separate samplers and images, HLSL.
// One source, every backend: ordinary Vulkan GLSL (gl_VertexIndex, push constants, set = N, separate
// texture and sampler) and HLSL pack for OpenGL unchanged, translated from their Vulkan SPIR-V; what
// OpenGL 4.5 has no form for is one error at the shader slot naming the feature.
TEST_F(PackagerCli, OpenGlTranslatesVulkanSourcesAndRefusesWhatItCannotExpress) {
  std::ofstream(dir_ / "vk_only.vert") << "#version 450\n"
                                          "layout(location = 0) out vec2 uv;\n"
                                          "void main() { uv = vec2(gl_VertexIndex & 1, gl_InstanceIndex);\n"
                                          "  gl_Position = vec4(uv, 0, 1); }\n";
  std::ofstream(dir_ / "vk_only.frag")
      << "#version 450\n"
         "layout(push_constant) uniform P { vec4 tint; } p;\n"
         "layout(set = 1, binding = 0) uniform texture2D tex;\n"
         "layout(set = 0, binding = 3) uniform sampler smp;\n"
         "layout(set = 2, binding = 0) uniform U { vec4 bias; };\n"
         "layout(location = 0) in vec2 uv;\n"
         "layout(location = 0) out vec4 color;\n"
         "void main() { color = p.tint * texture(sampler2D(tex, smp), uv) + bias; }\n";
  std::ofstream(dir_ / "ps.hlsl") << "Texture2D g_T; SamplerState g_T_sampler;\n"
                                     "float4 main(float4 pos : SV_Position, float2 uv : UV) : SV_Target "
                                     "{ return g_T.Sample(g_T_sampler, uv) + pos; }\n";
  const fs::path vk_json = dir_ / "vk_only.json", vk_spk = dir_ / "vk_only.spk";
  std::ofstream(vk_json) << R"({"Pipelines": [
    {"PSODesc": {"Name": "Vulkan GLSL PSO"}, "GraphicsPipeline": {"RTVFormats": {"0": "RGBA8_UNORM"}},
     "pVS": {"Desc": {"Name": "Vulkan VS"}, "FilePath": "vk_only.vert"},
     "pPS": {"Desc": {"Name": "Push PS"}, "FilePath": "vk_only.frag"}},
    {"PSODesc": {"Name": "HLSL PSO"}, "GraphicsPipeline": {"RTVFormats": {"0": "RGBA8_UNORM"}},
     "pVS": {"Desc": {"Name": "Vulkan VS"}, "FilePath": "vk_only.vert"},
     "pPS": {"Desc": {"Name": "HLSL PS"}, "FilePath": "ps.hlsl", "EntryPoint": "main"}}]})";
  CliRun both =
      statepack("pack -i '" + vk_json.string() + "' -o '" + vk_spk.string() + "' --vulkan --opengl");
  ASSERT_EQ(both.exit_code, 0) << both.output;
  CliRun text = statepack("inspect '" + vk_spk.string() + "'");
  // Sets flattened in declaration order (set, then binding) per kind; the push constants a uniform block
  // after the others; the separate pair one texture under the image's name; HLSL's g_T + g_T_sampler
  // one texture g_T (Diligent's convention).
  for (const char* line :
       {"OpenGL pipeline 'Vulkan GLSL PSO' (graphics)\n", "  uniform buffer 0: 'U' x1 [\"PIXEL\"]\n",
        "  uniform buffer 1: '$PushConstants' x1 [\"PIXEL\"]\n", "  texture 0: 'tex' x1 [\"PIXEL\"]\n",
        "OpenGL pipeline 'HLSL PSO' (graphics)\n", "  texture 0: 'g_T' x1 [\"PIXEL\"]\n"})
    EXPECT_NE(text.output.find(line), std::string::npos) << line << text.output;
  EXPECT_EQ(text.output.find("g_T_sampler' x1 [\"PIXEL\"]\n  TRIANGLE_LIST"), std::string::npos);
  // OpenGL alone packs them too.
  EXPECT_EQ(statepack("pack -i '" + vk_json.string() + "' -o '" + vk_spk.string() + "' --opengl").exit_code,
            0);

  // What OpenGL 4.5 cannot express: named once, at the shader slot, no glslang message about
  // generated text; no archive.
  std::ofstream(dir_ / "draw_parameters.vert")
      << "#version 450\n#extension GL_ARB_shader_draw_parameters : require\n"
         "void main() { gl_Position = vec4(gl_BaseInstanceARB, 0, 0, 1); }\n";
  const fs::path refused_json = dir_ / "refused.json", refused_spk = dir_ / "refused.spk";
  std::ofstream(refused_json) << R"({"Pipelines": [
    {"PSODesc": {"Name": "Draw Parameters PSO"}, "GraphicsPipeline": {"RTVFormats": {"0": "RGBA8_UNORM"}},
     "pVS": {"Desc": {"Name": "Base Instance VS"}, "FilePath": "draw_parameters.vert"}}]})";
  CliRun refused = statepack("pack -i '" + refused_json.string() + "' -o '" + refused_spk.string() +
                             "' --vulkan --opengl");
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  const std::string message =
      "refused.json:3:13: error: shader 'Base Instance VS' (OpenGL): uses draw parameters (gl_BaseVertex, "
      "gl_BaseInstance, gl_DrawID), which OpenGL 4.5 does not have [/Pipelines/0/pVS]";
  EXPECT_NE(refused.output.find(message), std::string::npos) << refused.output;
  EXPECT_EQ(refused.output.find(message), refused.output.rfind(message)) << refused.output;
  EXPECT_NE(refused.output.find("statepack: 1 error(s); no archive written"), std::string::npos)
      << refused.output;
  EXPECT_FALSE(fs::exists(refused_spk));
  EXPECT_EQ(statepack("pack -i '" + refused_json.string() + "' -o '" + refused_spk.string() + "' --vulkan")
                .exit_code,
            0);

  // Each stage its own view of the push constants is ordinary Vulkan; OpenGL links one block definition,
  // so views that agree where they overlap are merged (tests/gl draws them), and views that conflict are
  // a pack error naming both members and shaders, never a link failure at run time.
  std::ofstream(dir_ / "range_a.vert")
      << "#version 450\nlayout(push_constant) uniform P { vec4 offset; } p;\n"
         "void main() { gl_Position = p.offset; }\n";
  std::ofstream(dir_ / "range_b.frag")
      << "#version 450\n"
         "layout(push_constant) uniform P { layout(offset = 16) vec4 tint; } p;\n"
         "layout(location = 0) out vec4 color;\nvoid main() { color = p.tint; }\n";
  std::ofstream(dir_ / "range_c.frag")
      << "#version 450\n"
         "layout(push_constant) uniform P { layout(offset = 4) float gain; } p;\n"
         "layout(location = 0) out vec4 color;\nvoid main() { color = vec4(p.gain); }\n";
  const fs::path ranges_json = dir_ / "ranges.json";
  std::ofstream(ranges_json) << R"({"Pipelines": [
    {"PSODesc": {"Name": "Ranges PSO"}, "GraphicsPipeline": {"RTVFormats": {"0": "RGBA8_UNORM"}},
     "pVS": {"Desc": {"Name": "Range A VS"}, "FilePath": "range_a.vert"},
     "pPS": {"Desc": {"Name": "Range B PS"}, "FilePath": "range_b.frag"}},
    {"PSODesc": {"Name": "Overlapping Ranges PSO"}, "GraphicsPipeline": {"RTVFormats": {"0": "RGBA8_UNORM"}},
     "pVS": "Range A VS",
     "pPS": {"Desc": {"Name": "Range C PS"}, "FilePath": "range_c.frag"}}]})";
  CliRun ranges = statepack("pack -i '" + ranges_json.string() + "' -o '" + (dir_ / "ranges.spk").string() +
                            "' --vulkan --opengl");
  EXPECT_EQ(ranges.exit_code, 1) << ranges.output;
  EXPECT_NE(
      ranges.output.find("error: pipeline 'Overlapping Ranges PSO' (OpenGL): its stages declare the push "
                         "constants differently, and OpenGL links one definition per block: 'offset' (16 "
                         "bytes at offset 0) in vertex shader 'Range A VS' and 'gain' (4 bytes at offset 4) "
                         "in pixel shader 'Range C PS' overlap"),
      std::string::npos)
      << ranges.output;
  EXPECT_EQ(ranges.output.find("'Ranges PSO' (OpenGL)"), std::string::npos) << "merged: " << ranges.output;
  EXPECT_EQ(
      statepack("pack -i '" + ranges_json.string() + "' -o '" + (dir_ / "ranges.spk").string() + "' --vulkan")
          .exit_code,
      0);

  // A source that tests VULKAN is compiled for OpenGL from its own text (its author wrote per-backend
  // code): a separate sampler left in the OpenGL branch is named, not a glslang syntax error.
  const fs::path shader = dir_ / "separate.frag", json = dir_ / "separate.json";
  std::ofstream(shader) << "#version 450\n"
                           "#ifdef VULKAN\n#define TINT vec4(1)\n#else\n#define TINT vec4(0.5)\n#endif\n"
                           "layout(binding = 0) uniform texture2D tex;\n"
                           "layout(binding = 1) uniform sampler smp;\n"
                           "layout(location = 0) out vec4 color;\n"
                           "void main() { color = TINT * texture(sampler2D(tex, smp), vec2(0.5)); }\n";
  std::ofstream(json) << R"({"Pipelines": [{"PSODesc": {"Name": "Separate PSO"},
    "GraphicsPipeline": {"RTVFormats": {"0": "RGBA8_UNORM"}},
    "pVS": {"Desc": {"Name": "VS"}, "FilePath": ")"
                      << STATEPACK_SHADER_DIR << R"(/fullscreen_triangle.vert"},
    "pPS": {"Desc": {"Name": "Separate PS"}, "FilePath": "separate.frag"}}]})";
  CliRun separate = statepack("pack -i '" + json.string() + "' -o '" + (dir_ / "separate.spk").string() +
                              "' --vulkan --opengl");
  EXPECT_EQ(separate.exit_code, 1) << separate.output;
  EXPECT_NE(separate.output.find("separate.json:4:12: error: shader 'Separate PS' (OpenGL): declares 'tex' "
                                 "(sampled image), 'smp' (sampler) when VULKAN is not defined"),
            std::string::npos)
      << separate.output;
  EXPECT_EQ(separate.output.find("unexpected IDENTIFIER"), std::string::npos) << separate.output;
  CliRun vulkan_only =
      statepack("pack -i '" + json.string() + "' -o '" + (dir_ / "separate.spk").string() + "' --vulkan");
  EXPECT_EQ(vulkan_only.exit_code, 0) << vulkan_only.output;  // Vulkan has separate samplers
}

}  // namespace

namespace {

// The path tracer's states pack for both backends (its shaders say `#ifdef VULKAN` where they differ).
TEST_F(PackagerCli, PathTracerStatesPackForOpenGlToo) {
  const fs::path out = dir_ / "path_tracer.spk";
  CliRun pack =
      statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/path_tracer.json", out) + " --opengl");
  ASSERT_EQ(pack.exit_code, 0) << pack.output;
  CliRun text = statepack("inspect '" + out.string() + "'");
  for (const char* line :
       {"OpenGL pipeline 'Path Trace PSO' (compute)\n", "  image 4: 'accumulation' x1 [\"COMPUTE\"]\n",
        "OpenGL pipeline 'Resolve PSO' (graphics)\n", "  uniform buffer 0: 'Params' x1 [\"PIXEL\"]\n",
        "  push constants: 8 bytes\n"})  // resolve.frag: exposure and divisor
    EXPECT_NE(text.output.find(line), std::string::npos) << line << "\nin:\n" << text.output;
}

// merge keeps the OpenGL block: a Vulkan-only and an OpenGL-only archive of the slice merge into one with
// both backends, each pipeline once per backend.
TEST_F(PackagerCli, MergeKeepsTheOpenGlBlock) {
  const std::string input = std::string(STATEPACK_STATES_DIR) + "/slice.json";
  const fs::path vk = dir_ / "vk.spk", gl = dir_ / "gl.spk", both = dir_ / "both.spk",
                 merged = dir_ / "merged.spk";
  for (const auto& [out, flags] :
       {std::pair{vk, "--vulkan"}, {gl, "--opengl"}, {both, "--vulkan --opengl"}}) {
    CliRun pack = statepack("pack -i '" + input + "' -s '" + STATEPACK_SHADER_DIR + "' -o '" + out.string() +
                            "' " + flags);
    ASSERT_EQ(pack.exit_code, 0) << pack.output;
  }
  CliRun run = statepack("merge -o '" + merged.string() + "' '" + vk.string() + "' '" + gl.string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  CliRun text = statepack("inspect '" + merged.string() + "'");
  EXPECT_NE(text.output.find("backends: [\"vulkan\",\"opengl\"]"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("OpenGL pipeline 'Fill Buffer PSO' (compute)"), std::string::npos)
      << text.output;
  EXPECT_NE(text.output.find("\npipeline 'Fill Buffer PSO' (compute)"), std::string::npos) << text.output;
  // The same objects as packing both at once (the order of blobs may differ; the listing of pipelines not).
  CliRun direct = statepack("inspect '" + both.string() + "'");
  auto pipelines_part = [](const std::string& s) { return s.substr(s.find("\npipeline '")); };
  EXPECT_EQ(pipelines_part(text.output).size(), pipelines_part(direct.output).size());
  // The same OpenGL pipelines in several inputs merge into one of each.
  CliRun repeated = statepack("merge -o '" + (dir_ / "x.spk").string() + "' '" + gl.string() + "' '" +
                              both.string() + "' '" + gl.string() + "'");
  EXPECT_EQ(repeated.exit_code, 0) << repeated.output;
}

}  // namespace

namespace {

// Found by review: what --opengl accepted must load, and what it leaves out must not stop it.
TEST_F(PackagerCli, OpenGlPackingEdgeCases) {
  // A loose uniform (no block) under #ifndef VULKAN: OpenGL could bind it only by location, which the
  // runtime does not do, so pack refuses it instead of writing an archive that would not load.
  std::ofstream(dir_ / "loose.comp")
      << "#version 450\nlayout(local_size_x = 1) in;\n"
         "layout(binding = 0) buffer Out { float v[]; };\n"
         "#ifdef VULKAN\nlayout(push_constant) uniform P { float k; } p;\n#define K p.k\n"
         "#else\nlayout(location = 0) uniform float k;\n#define K k\n#endif\n"
         "void main() { v[0] = K; }\n";
  std::ofstream(dir_ / "loose.json")
      << R"({"Pipelines": [{"PSODesc": {"Name": "Loose PSO"}, "pCS": {"Desc": {"Name": "Loose CS"}, "FilePath": "loose.comp"}}]})";
  CliRun loose = statepack("pack -i '" + (dir_ / "loose.json").string() + "' -o '" +
                           (dir_ / "loose.spk").string() + "' --vulkan --opengl");
  EXPECT_EQ(loose.exit_code, 1) << loose.output;
  EXPECT_NE(loose.output.find("a uniform outside a block"), std::string::npos) << loose.output;
  EXPECT_FALSE(fs::exists(dir_ / "loose.spk"));

  // A standalone HLSL shader (a Vulkan object only) does not stop the OpenGL block.
  std::ofstream(dir_ / "vs.hlsl")
      << "float4 main(uint id : SV_VertexID) : SV_Position { return float4(id, 0, 0, 1); }\n";
  std::ofstream(dir_ / "standalone.json")
      << R"({"Shaders": [{"Desc": {"Name": "HLSL VS", "ShaderType": "VERTEX"},
      "FilePath": "vs.hlsl", "EntryPoint": "main"}],
    "Pipelines": [{"PSODesc": {"Name": "Fill Buffer PSO"},
      "pCS": {"Desc": {"Name": "Fill Buffer CS"}, "FilePath": ")"
      << STATEPACK_SHADER_DIR << R"(/fill_buffer.comp"}}]})";
  CliRun both = statepack("pack -i '" + (dir_ / "standalone.json").string() + "' -o '" +
                          (dir_ / "standalone.spk").string() + "' --vulkan --opengl");
  EXPECT_EQ(both.exit_code, 0) << both.output;
  // OpenGL alone says what it leaves out.
  CliRun alone = statepack("pack -i '" + (dir_ / "standalone.json").string() + "' -o '" +
                           (dir_ / "alone.spk").string() + "' --opengl");
  EXPECT_EQ(alone.exit_code, 0) << alone.output;
  EXPECT_NE(alone.output.find("warning: --opengl alone stores pipelines only"), std::string::npos)
      << alone.output;

  // 64-bit specialization constants: Vulkan takes them, glSpecializeShader does not.
  std::ofstream(dir_ / "wide.comp")
      << "#version 450\nlayout(local_size_x = 1) in;\n"
         "layout(constant_id = 0) const double kWide = 1.0;\n"
         "layout(binding = 0) buffer Out { double v[]; };\nvoid main() { v[0] = kWide; }\n";
  std::ofstream(dir_ / "wide.json") << R"({"Pipelines": [{"PSODesc": {"Name": "Wide PSO"},
    "pCS": {"Desc": {"Name": "Wide CS"}, "FilePath": "wide.comp"},
    "pSpecializationConstants": [{"Name": "kWide", "Value": 2.5}]}]})";
  CliRun wide = statepack("pack -i '" + (dir_ / "wide.json").string() + "' -o '" +
                          (dir_ / "wide.spk").string() + "' --vulkan --opengl");
  EXPECT_EQ(wide.exit_code, 1) << wide.output;
  EXPECT_NE(wide.output.find("pipeline 'Wide PSO' (OpenGL): specialization constant 'kWide' is 64-bit"),
            std::string::npos)
      << wide.output;
}

}  // namespace

namespace {

// BYTECODE: a module of another compiler, here written with SPIRV-Tools' assembler: two entry points, of
// which the shader's EntryPoint is kept (and the first of its stage without one, as in Diligent); a
// module of a later SPIR-V than --vulkan_version takes is an error naming both versions.
TEST_F(PackagerCli, BytecodeKeepsTheShadersEntryPointAndChecksItsVersion) {
  std::ofstream(dir_ / "two.spvasm") << R"(OpCapability Shader
OpMemoryModel Logical GLSL450
OpEntryPoint GLCompute %first "first"
OpEntryPoint GLCompute %second "second"
OpExecutionMode %first LocalSize 1 1 1
OpExecutionMode %second LocalSize 2 1 1
%void = OpTypeVoid
%fn = OpTypeFunction %void
%first = OpFunction %void None %fn
%a = OpLabel
OpReturn
OpFunctionEnd
%second = OpFunction %void None %fn
%b = OpLabel
OpReturn
OpFunctionEnd
)";
  ASSERT_EQ(
      statepack::testing::run_command("spirv-as --target-env vulkan1.0 -o '" + (dir_ / "two.spv").string() +
                                      "' '" + (dir_ / "two.spvasm").string() + "'")
          .exit_code,
      0);
  std::ofstream(dir_ / "bytecode.json") << R"({"Pipelines": [
    {"PSODesc": {"Name": "Second"}, "pCS": {"Desc": {"Name": "Second CS"}, "SourceLanguage": "BYTECODE",
     "FilePath": "two.spv", "EntryPoint": "second"}},
    {"PSODesc": {"Name": "Default"}, "pCS": {"Desc": {"Name": "Default CS"}, "SourceLanguage": "BYTECODE",
     "FilePath": "two.spv"}}]})";
  const fs::path spk = dir_ / "bytecode.spk", dump = dir_ / "bytecode_dump";
  CliRun pack = statepack_in(
      dir_, "pack -i bytecode.json -o '" + spk.string() + "' --vulkan -d '" + dump.string() + "'");
  ASSERT_EQ(pack.exit_code, 0) << pack.output;
  CliRun inspect = statepack("inspect --json '" + spk.string() + "'");
  EXPECT_NE(inspect.output.find(
                "\"name\": \"Second CS\",\n      \"stage\": \"COMPUTE\",\n      \"entry_point\": \"second\""),
            std::string::npos)
      << inspect.output;
  EXPECT_NE(inspect.output.find(
                "\"name\": \"Default CS\",\n      \"stage\": \"COMPUTE\",\n      \"entry_point\": \"first\""),
            std::string::npos)
      << inspect.output;
  // The module is cut to that entry point: the other and its execution mode are gone.
  const std::string kept = read_file(dump / "Vulkan" / "compute" / "Second" / "Second CS.spvasm");
  EXPECT_NE(kept.find("\"second\""), std::string::npos) << kept;
  EXPECT_NE(kept.find("LocalSize 2 1 1"), std::string::npos) << kept;
  EXPECT_EQ(kept.find("\"first\""), std::string::npos) << kept;
  EXPECT_EQ(kept.find("LocalSize 1 1 1"), std::string::npos) << kept;
  EXPECT_EQ(statepack("verify '" + spk.string() + "'").exit_code, 0);

  // SPIR-V 1.3 (Vulkan 1.1's): refused for Vulkan 1.0, packed for 1.1.
  ASSERT_EQ(
      statepack::testing::run_command("spirv-as --target-env vulkan1.1 -o '" + (dir_ / "two.spv").string() +
                                      "' '" + (dir_ / "two.spvasm").string() + "'")
          .exit_code,
      0);
  CliRun old = statepack_in(dir_, "pack -i bytecode.json -o '" + spk.string() + "' --vulkan");
  EXPECT_EQ(old.exit_code, 1) << old.output;
  EXPECT_NE(old.output.find("two.spv is SPIR-V 1.3, but --vulkan_version 1.0 takes SPIR-V 1.0 at most"),
            std::string::npos)
      << old.output;
  EXPECT_EQ(
      statepack_in(dir_, "pack -i bytecode.json -o '" + spk.string() + "' --vulkan --vulkan_version 1.1")
          .exit_code,
      0);
}

}  // namespace

namespace {

// inspect spells values as the notation does, with Vulkan's name beside a format (docs/cli.md,
// "Spellings"), and shows a specialization constant as the value of the type its shader declares.
TEST_F(PackagerCli, InspectSpellsAsTheNotationAndTypesConstants) {
  fs::path out = dir_ / "constants.spk";
  CliRun pack = statepack(pack_args(data("specialization/constants.json"), out, data("specialization")));
  ASSERT_EQ(pack.exit_code, 0) << pack.output;
  CliRun text = statepack("inspect '" + out.string() + "'");
  for (const char* line : {"  COMPUTE: 'Constants CS', ",
                           "    binding 0: 'Result' VK_DESCRIPTOR_TYPE_STORAGE_BUFFER x1 [\"COMPUTE\"]\n",
                           "  specialization constant 'kBase' (COMPUTE, id 0, uint) = 42\n",
                           "  specialization constant 'kNegate' (COMPUTE, id 2, bool) = true\n",
                           "  specialization constant 'kScale' (COMPUTE, id 1, float) = 1.5\n"})
    EXPECT_NE(text.output.find(line), std::string::npos) << line << "\nin:\n" << text.output;
  CliRun json = statepack("inspect --json '" + out.string() + "'");
  for (const char* field :
       {"\"type\": \"float\",\n          \"value\": 1.5,\n          \"bits\": \"0x3fc00000\"",
        "\"type\": \"bool\",\n          \"value\": true,\n          \"bits\": \"0x00000001\""})
    EXPECT_NE(json.output.find(field), std::string::npos) << field << "\nin:\n" << json.output;

  // A signed constant shows its sign, not its two's-complement bits.
  std::ofstream(dir_ / "signed.comp") << "#version 450\nlayout(local_size_x = 1) in;\n"
                                         "layout(constant_id = 3) const int kOffset = 0;\n"
                                         "layout(std430, binding = 0) buffer Out { int value; } result;\n"
                                         "void main() { result.value = kOffset; }\n";
  std::ofstream(dir_ / "signed.json") << R"({"Pipelines": [{"PSODesc": {"Name": "Signed"},
    "pCS": {"Desc": {"Name": "Signed CS", "ShaderType": "COMPUTE"}, "FilePath": "signed.comp"},
    "pSpecializationConstants": [{"Name": "kOffset", "ShaderStages": "COMPUTE", "Value": -5}]}]})";
  CliRun signed_pack = statepack_in(dir_, "pack -i signed.json -o signed.spk --vulkan");
  ASSERT_EQ(signed_pack.exit_code, 0) << signed_pack.output;
  CliRun signed_text = statepack("inspect '" + (dir_ / "signed.spk").string() + "'");
  EXPECT_NE(signed_text.output.find("  specialization constant 'kOffset' (COMPUTE, id 3, int) = -5\n"),
            std::string::npos)
      << signed_text.output;

  // A target format: the notation's name with Vulkan's in parentheses.
  fs::path targets = dir_ / "slice.spk";
  ASSERT_EQ(statepack(pack_args(std::string(STATEPACK_STATES_DIR) + "/slice.json", targets)).exit_code, 0);
  CliRun slice = statepack("inspect '" + targets.string() + "'");
  EXPECT_NE(
      slice.output.find(
          "  TRIANGLE_LIST, cull NONE, depth test off, targets: RGBA8_UNORM (VK_FORMAT_R8G8B8A8_UNORM)\n"),
      std::string::npos)
      << slice.output;
}

}  // namespace
