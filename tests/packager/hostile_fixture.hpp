// The fixtures of the hostile-input tests: statepack run in a fresh folder per test, under a time limit,
// and (HostileOutput) a small project whose files must never change.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "common/run_command.hpp"
#include "common/text_files.hpp"

namespace statepack::testing::hostile {

namespace fs = std::filesystem;
using CliRun = statepack::testing::CommandResult;

using statepack::testing::read_file;
using statepack::testing::write_file;

inline size_t count_lines_with(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// A compute pipeline whose shader is `file` (next to the notation).
inline std::string compute_pipeline(const std::string& name, const std::string& file) {
  return R"({"PSODesc": {"Name": ")" + name + R"("}, "pCS": {"Desc": {"Name": ")" + name +
         R"( CS", "ShaderType": "COMPUTE"}, "FilePath": ")" + file + R"("}})";
}

inline constexpr const char* kComputeShader =
    "#version 450\nlayout(local_size_x = 1) in;\n"
    "layout(set = 0, binding = 0) buffer Data { uint values[]; } data;\n"
    "void main() { data.values[0] = 1u; }\n";

// Runs statepack in `dir_` (so messages show short relative paths), under a time limit: a hang fails.
class HostileInput : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = statepack::testing::fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "hostile"); }
  CliRun statepack(const std::string& args, int seconds = 60) const {
    return statepack::testing::run_command("cd '" + dir_.string() + "' && timeout " +
                                           std::to_string(seconds) + " '" + STATEPACK_EXE + "' " + args);
  }
  CliRun pack(const std::string& input, const std::string& more = "-o out.spk") const {
    return statepack("pack -i " + input + " --vulkan " + more);
  }
  fs::path dir_;
};

class HostileOutput : public HostileInput {
 protected:
  void SetUp() override {
    HostileInput::SetUp();
    write_file(dir_ / "inc" / "common.glsl", "const uint kValue = 7u;\n");
    write_file(dir_ / "cs.comp",
               "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
               "#include \"inc/common.glsl\"\nlayout(local_size_x = 1) in;\n"
               "layout(set = 0, binding = 0) buffer Data { uint v[]; } data;\n"
               "void main() { data.v[0] = kValue; }\n");
    write_file(dir_ / "base.json", "{\"Pipelines\": [" + compute_pipeline("P", "cs.comp") + "]}");
    write_file(dir_ / "a.json", "{\"Imports\": [\"base.json\"]}");
    for (const char* f : {"a.json", "base.json", "cs.comp", "inc/common.glsl"})
      before_[f] = read_file(dir_ / f);
  }
  void expect_inputs_unchanged() {
    for (const auto& [name, text] : before_)
      EXPECT_EQ(read_file(dir_ / name), text) << name << " was changed";
  }
  std::map<std::string, std::string> before_;
};

}  // namespace statepack::testing::hostile
