// The notation corpus: every file under tests/corpus/valid packs, and its archive's
// `statepack inspect --json` matches the golden beside it; every file under tests/corpus/invalid
// with a .expected sidecar (packed with the options of its .args sidecar, if any) fails with exit code 1
// and prints each line of that sidecar exactly once (it may end with the "statepack: N error(s)" summary,
// which pins the count); every file under tests/corpus/warnings packs and prints its sidecar's warnings.
// Regenerate goldens after an intended change with: STATEPACK_UPDATE_GOLDENS=1 ctest -R NotationCorpus
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/run_command.hpp"

namespace {

namespace fs = std::filesystem;

using CliRun = statepack::testing::CommandResult;

CliRun run_in(const fs::path& dir, const std::string& args) {
  return statepack::testing::run_command("cd '" + dir.string() + "' && '" + STATEPACK_EXE + "' " + args);
}

std::string read_file(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

std::vector<fs::path> files(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == extension) out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

const fs::path kCorpus = STATEPACK_CORPUS_DIR;
const fs::path kOutput = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "corpus";

TEST(NotationCorpus, ValidFilesPackAndMatchTheirGoldens) {
  fs::create_directories(kOutput);
  const bool update = std::getenv("STATEPACK_UPDATE_GOLDENS") != nullptr;
  auto inputs = files(kCorpus / "valid", ".json");
  ASSERT_GE(inputs.size(), 5u);
  for (const fs::path& input : inputs) {
    SCOPED_TRACE(input.filename().string());
    fs::path archive = kOutput / (input.stem().string() + ".spk");
    CliRun pack = run_in(input.parent_path(), "pack -i '" + input.filename().string() +
                                                  "' -s ../shaders -o '" + archive.string() + "' --vulkan");
    ASSERT_EQ(pack.exit_code, 0) << pack.output;
    CliRun inspect = run_in(kOutput, "inspect --json '" + archive.string() + "'");
    ASSERT_EQ(inspect.exit_code, 0) << inspect.output;
    // The producer is this build, whatever its version: a release does not rewrite every golden.
    const std::string producer = "\"producer_version\": \"" STATEPACK_PROJECT_VERSION "\"";
    const size_t at = inspect.output.find(producer);
    ASSERT_NE(at, std::string::npos) << inspect.output;
    inspect.output.replace(at, producer.size(), "\"producer_version\": \"(this build)\"");
    fs::path golden = input;
    golden.replace_extension(".golden");
    if (update) {
      std::ofstream(golden, std::ios::binary) << inspect.output;
      continue;
    }
    ASSERT_TRUE(fs::exists(golden)) << "no golden; create it with STATEPACK_UPDATE_GOLDENS=1";
    EXPECT_EQ(inspect.output, read_file(golden)) << "inspect --json differs from " << golden;
  }
}

// Each non-empty line of `expected` appears in `output` exactly once: an error reported for every shader
// that includes a file, say, is a failure too.
void expect_each_line_once(const fs::path& expected, const std::string& output) {
  std::istringstream lines(read_file(expected));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    size_t count = 0;
    for (size_t at = output.find(line); at != std::string::npos; at = output.find(line, at + 1)) ++count;
    EXPECT_EQ(count, 1u) << "expected once: " << line << "\n" << output;
  }
}

// One source, every backend: every valid file packs for OpenGL too (translated from Vulkan, or from its
// own text where it tests VULKAN), and what it writes loads (pack checks that before writing).
TEST(NotationCorpus, ValidFilesPackForOpenGlToo) {
  fs::create_directories(kOutput);
  auto inputs = files(kCorpus / "valid", ".json");
  ASSERT_GE(inputs.size(), 5u);
  for (const fs::path& input : inputs) {
    SCOPED_TRACE(input.filename().string());
    fs::path archive = kOutput / (input.stem().string() + "_gl.spk");
    CliRun pack =
        run_in(input.parent_path(), "pack -i '" + input.filename().string() + "' -s ../shaders -o '" +
                                        archive.string() + "' --vulkan --opengl");
    ASSERT_EQ(pack.exit_code, 0) << pack.output;
    CliRun inspect = run_in(kOutput, "inspect --json '" + archive.string() + "'");
    ASSERT_EQ(inspect.exit_code, 0) << inspect.output;
    EXPECT_NE(inspect.output.find("\"opengl\""), std::string::npos) << inspect.output;
  }
}

TEST(NotationCorpus, InvalidFilesFailWithTheExpectedErrors) {
  auto expectations = files(kCorpus / "invalid", ".expected");
  ASSERT_GE(expectations.size(), 8u);
  for (const fs::path& expected : expectations) {
    fs::path input = expected;
    input.replace_extension(".json");
    SCOPED_TRACE(input.filename().string());
    // A NAME.args sidecar adds options (--strict for what is otherwise a warning).
    fs::path args_file = expected;
    args_file.replace_extension(".args");
    std::string args = fs::exists(args_file) ? read_file(args_file) : "";
    while (!args.empty() && (args.back() == '\n' || args.back() == ' ')) args.pop_back();
    CliRun pack =
        run_in(input.parent_path(), "pack -i '" + input.filename().string() + "' -s ../shaders -o '" +
                                        (kOutput / "invalid.spk").string() + "' --vulkan " + args);
    EXPECT_EQ(pack.exit_code, 1) << pack.output;
    expect_each_line_once(expected, pack.output);
  }
}

// Every file under tests/corpus/warnings packs (exit 0: what Diligent accepts, statepack accepts) and
// prints each line of its .expected sidecar exactly once: the warnings that say what the user should know.
TEST(NotationCorpus, WarningFilesPackWithTheExpectedWarnings) {
  auto expectations = files(kCorpus / "warnings", ".expected");
  ASSERT_GE(expectations.size(), 3u);
  for (const fs::path& expected : expectations) {
    fs::path input = expected;
    input.replace_extension(".json");
    SCOPED_TRACE(input.filename().string());
    CliRun pack =
        run_in(input.parent_path(), "pack -i '" + input.filename().string() + "' -s ../shaders -o '" +
                                        (kOutput / "warnings.spk").string() + "' --vulkan");
    EXPECT_EQ(pack.exit_code, 0) << pack.output;
    expect_each_line_once(expected, pack.output);
  }
}

}  // namespace
