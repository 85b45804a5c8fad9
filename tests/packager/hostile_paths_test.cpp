// Paths and depths from input: an output never replaces an input of the same run however the path
// reaches it (verify's pipeline cache included), a file is one file however it is imported, depfiles
// are read back by the real Make and Ninja, no nesting depth in the input can crash the packer, and
// what cannot be loaded is named safely on the terminal.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <utime.h>

#include <filesystem>
#include <string>
#include <vector>

#include "hostile_fixture.hpp"

namespace {

using namespace statepack::testing::hostile;

// --- outputs and inputs -------------------------------------------------------------------------------

TEST_F(HostileOutput, VerifyNeverWritesItsCacheOverAnArchiveOrTheVariantsFile) {
  ASSERT_EQ(pack("a.json", "-o out.spk").exit_code, 0);
  const std::string archive = read_file(dir_ / "out.spk");
  fs::create_directories(dir_ / "sub");
  fs::create_hard_link(dir_ / "out.spk", dir_ / "hard.spk");
  fs::create_symlink(dir_ / "out.spk", dir_ / "link.spk");
  for (const std::string& cache :
       std::vector<std::string>{"out.spk", "sub/../out.spk", "hard.spk", (dir_ / "out.spk").string()}) {
    CliRun run = statepack("verify out.spk --cache '" + cache + "'");
    EXPECT_EQ(run.exit_code, 2) << cache << "\n" << run.output;
    EXPECT_NE(
        run.output.find("statepack: error: --cache: refusing to write '" + cache + "': it is the input"),
        std::string::npos)
        << run.output;
    EXPECT_EQ(run.output.find("device:"), std::string::npos) << "no work before the refusal: " << run.output;
    EXPECT_EQ(read_file(dir_ / "out.spk"), archive) << cache;
  }
  CliRun link = statepack("verify out.spk --cache link.spk");
  EXPECT_EQ(link.exit_code, 2) << link.output;
  EXPECT_NE(link.output.find("it is a symbolic link"), std::string::npos) << link.output;
  write_file(dir_ / "v.json", "{\"statepack_variants\": 1, \"variants\": []}");
  CliRun variants = statepack("verify out.spk --variants v.json --cache v.json");
  EXPECT_EQ(variants.exit_code, 2) << variants.output;
  EXPECT_NE(variants.output.find("it is the input"), std::string::npos) << variants.output;
  EXPECT_EQ(read_file(dir_ / "out.spk"), archive);
  // A new cache file is written (and the archive left alone).
  CliRun fresh = statepack("verify out.spk --cache new.cache");
  EXPECT_EQ(fresh.exit_code, 0) << fresh.output;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "new.cache"));
  EXPECT_EQ(read_file(dir_ / "out.spk"), archive);
}

// --- one file, however it is imported ------------------------------------------------------------------

TEST_F(HostileInput, AFileImportedByAnyOfItsNamesIsReadOnce) {
  write_file(dir_ / "cs.comp", kComputeShader);
  write_file(dir_ / "base.json", "{\"Pipelines\": [" + compute_pipeline("P", "cs.comp") + "]}");
  fs::create_directories(dir_ / "sub");
  fs::create_hard_link(dir_ / "base.json", dir_ / "hard.json");
  fs::create_symlink(dir_ / "base.json", dir_ / "link.json");
  write_file(dir_ / "a.json",
             "{\"Imports\": [\"base.json\", \"hard.json\", \"link.json\", \"sub/../base.json\"]}");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output.find("defined twice"), std::string::npos) << run.output;
  // A cycle through another name of the same file is a cycle (a warning, as Diligent skips it).
  write_file(dir_ / "c.json",
             "{\"Imports\": [\"c_hard.json\"], \"Pipelines\": [" + compute_pipeline("C", "cs.comp") + "]}");
  fs::create_hard_link(dir_ / "c.json", dir_ / "c_hard.json");
  CliRun cycle = pack("c.json");
  EXPECT_EQ(cycle.exit_code, 0) << cycle.output;
  EXPECT_NE(cycle.output.find("warning: import cycle: c.json -> c.json"), std::string::npos) << cycle.output;
  EXPECT_EQ(cycle.output.find("defined twice"), std::string::npos) << cycle.output;
}

// --- depth --------------------------------------------------------------------------------------------

TEST_F(HostileInput, ThousandsOfChainedImportsAreReadWithoutRecursion) {
  // Each file imports the next; the last defines the pipeline. Before, the reader recursed per import
  // and a few thousand overflowed its stack.
  constexpr int kFiles = 20000;
  write_file(dir_ / "cs.comp", kComputeShader);
  for (int i = 0; i < kFiles; ++i)
    write_file(dir_ / "chain" / (std::to_string(i) + ".json"),
               i + 1 < kFiles ? "{\"Imports\": [\"" + std::to_string(i + 1) + ".json\"]}"
                              : "{\"Pipelines\": [" + compute_pipeline("Deep", "../cs.comp") + "]}");
  CliRun run = pack("chain/0.json", "-o out.spk --print_contents");
  EXPECT_EQ(run.exit_code, 0) << run.output.substr(0, 2000);
  EXPECT_NE(run.output.find("Deep"), std::string::npos) << run.output.substr(0, 2000);
}

// A shader of `terms` operands in one sum (GLSL, or HLSL), and its notation.
void write_sum_shader(const fs::path& dir, size_t terms, bool hlsl) {
  std::string sum = "v";
  for (size_t i = 1; i < terms; ++i) sum += "+v";
  write_file(dir / (hlsl ? "sum.hlsl" : "sum.comp"),
             hlsl ? "RWStructuredBuffer<float> d : register(u0);\n[numthreads(1, 1, 1)] void main() {\n"
                    "  float v = d[0];\n  d[1] = " +
                        sum + ";\n}\n"
                  : "#version 450\nlayout(local_size_x = 1) in;\n"
                    "layout(set = 0, binding = 0) buffer D { float v[]; } d;\nvoid main() {\n"
                    "  float v = d.v[0];\n  d.v[1] = " +
                        sum + ";\n}\n");
  write_file(dir / "sum.json",
             std::string("{\"Pipelines\": [{\"PSODesc\": {\"Name\": \"Sum\"}, \"pCS\": {\"Desc\": "
                         "{\"Name\": \"Sum CS\", \"ShaderType\": \"COMPUTE\"}, "
                         "\"SourceLanguage\": \"") +
                 (hlsl ? "HLSL\", \"FilePath\": \"sum.hlsl\"" : "GLSL\", \"FilePath\": \"sum.comp\"") +
                 "}}]}");
}

TEST_F(HostileInput, DeepExpressionsCompileOrAreRefusedByNameNeverACrash) {
  for (bool hlsl : {false, true}) {
    SCOPED_TRACE(hlsl ? "HLSL" : "GLSL");
    // 20,000 terms (40 KB): a crash inside glslang before, on an 8 MiB stack; now it packs for both
    // backends, and --check does the same work.
    write_sum_shader(dir_, 20000, hlsl);
    CliRun both = statepack("pack -i sum.json --vulkan --opengl -o sum.spk");
    EXPECT_EQ(both.exit_code, 0) << both.output;
    EXPECT_EQ(statepack("pack -i sum.json --vulkan --check").exit_code, 0);
    // Past the bound: an error naming the shader and the bound, before any recursion.
    write_sum_shader(dir_, 140000, hlsl);
    CliRun deep = statepack("pack -i sum.json --vulkan --check");
    EXPECT_EQ(deep.exit_code, 1) << deep.output;
    EXPECT_NE(deep.output.find("error: shader 'Sum CS': nests too deeply to compile safely"),
              std::string::npos)
        << deep.output;
    EXPECT_NE(deep.output.find("statepack compiles up to 262144"), std::string::npos) << deep.output;
  }
}

TEST_F(HostileInput, DeeplyNestedBracketsAndMacroArgumentsAreRefusedByName) {
  // F(F(F(...))) 50,000 deep: the preprocessor would recurse once per level.
  std::string nested = "v";
  for (int i = 0; i < 50000; ++i) nested = "F(" + nested;
  nested += std::string(50000, ')');
  write_file(dir_ / "macro.comp", std::string("#version 450\n#define F(x) (x)\nlayout(local_size_x = 1) in;\n"
                                              "layout(set = 0, binding = 0) buffer D { float v[]; } d;\n"
                                              "void main() {\n  float v = d.v[0];\n  d.v[1] = ") +
                                      nested + ";\n}\n");
  write_file(dir_ / "macro.json", "{\"Pipelines\": [" + compute_pipeline("M", "macro.comp") + "]}");
  CliRun run = pack("macro.json", "--check");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("macro.comp:7: brackets nest 50001 deep here; statepack compiles up to 10000"),
            std::string::npos)
      << run.output;
  // The same in an #include: named there.
  write_file(dir_ / "inc.glsl",
             "float deep() { return " + std::string(20000, '(') + "1.0" + std::string(20000, ')') + "; }\n");
  write_file(dir_ / "inc.comp",
             "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"inc.glsl\"\n"
             "layout(local_size_x = 1) in;\nvoid main() {}\n");
  write_file(dir_ / "inc.json", "{\"Pipelines\": [" + compute_pipeline("I", "inc.comp") + "]}");
  CliRun include = pack("inc.json", "--check");
  EXPECT_EQ(include.exit_code, 1) << include.output;
  EXPECT_NE(include.output.find("#include \"inc.glsl\": inc.glsl:1: brackets nest 20001 deep here"),
            std::string::npos)
      << include.output;
}

// --- depfiles -----------------------------------------------------------------------------------------

// The depfile of a pack whose shader and include have names Make and Ninja read specially (a space, '#',
// '$', ':', '%', '!', '(', '@', '~', a non-ASCII letter, a backslash inside a name) is read back by both
// as those very files: Make rebuilds when any one of them changes and not otherwise; Ninja records each.
TEST_F(HostileInput, DepfilesAreReadBackByMakeAndNinjaAsTheFilesThemselves) {
  const std::string folder = "odd dir #1 $x:y %z (w)!@~\xC3\xA9";
  write_file(dir_ / folder / "in\\c.glsl", "const uint kValue = 7u;\n");
  write_file(dir_ / folder / "c s.comp",
             "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"in\\c.glsl\"\n"
             "layout(local_size_x = 1) in;\nlayout(set = 0, binding = 0) buffer D { uint v[]; } d;\n"
             "void main() { d.v[0] = kValue; }\n");
  write_file(dir_ / "odd.json", "{\"Pipelines\": [" + compute_pipeline("P", folder + "/c s.comp") + "]}");
  CliRun pack_run = pack("odd.json", "-o out.spk --depfile out.d");
  ASSERT_EQ(pack_run.exit_code, 0) << pack_run.output;
  const std::vector<fs::path> inputs = {dir_ / "odd.json", dir_ / folder / "c s.comp",
                                        dir_ / folder / "in\\c.glsl"};
  write_file(dir_ / "Makefile", "out.spk:\n\ttouch out.spk\ninclude out.d\n");
  auto make_question = [&] {
    return statepack::testing::run_command("cd '" + dir_.string() + "' && make -q out.spk 2>&1");
  };
  // Everything older than the archive: up to date (exit 0; a name Make misread would be exit 2).
  for (const fs::path& f : inputs) {
    struct utimbuf old_times {
      1000000000, 1000000000
    };
    ASSERT_EQ(::utime(f.c_str(), &old_times), 0) << f;
  }
  CliRun fresh = make_question();
  EXPECT_EQ(fresh.exit_code, 0) << read_file(dir_ / "out.d") << fresh.output;
  for (const fs::path& f : inputs) {
    struct utimbuf new_times {
      2000000000, 2000000000
    };
    ASSERT_EQ(::utime(f.c_str(), &new_times), 0);
    CliRun stale = make_question();
    EXPECT_EQ(stale.exit_code, 1) << f << " changed, and Make did not see it:\n"
                                  << read_file(dir_ / "out.d") << stale.output;
    struct utimbuf old_times {
      1000000000, 1000000000
    };
    ASSERT_EQ(::utime(f.c_str(), &old_times), 0);
  }
  // Ninja reads the same depfile (deps = gcc keeps what it read in its log).
  fs::copy_file(dir_ / "out.d", dir_ / "saved.d");
  write_file(dir_ / "build.ninja",
             "rule pack\n  command = cp saved.d out.d && touch out.spk\n  depfile = out.d\n  deps = gcc\n"
             "build out.spk: pack\n");
  CliRun ninja =
      statepack::testing::run_command("cd '" + dir_.string() + "' && ninja && ninja -t deps out.spk");
  ASSERT_EQ(ninja.exit_code, 0) << ninja.output;
  for (const fs::path& f : inputs)
    EXPECT_NE(ninja.output.find("    " + f.string() + "\n"), std::string::npos)
        << f << " not among Ninja's deps:\n"
        << ninja.output << read_file(dir_ / "saved.d");
}

TEST_F(HostileInput, DepfilePathsNeitherToolCanReadAreRefusedByCharacter) {
  const std::string refusal =
      "which Make and Ninja cannot both read in a depfile; rename it, or pack without --depfile";
  for (const std::string& name :
       std::vector<std::string>{"a*b", "a?b", "a[b]", "a=b", "a;b", "a|b", "a'b", "a&b"}) {
    write_file(dir_ / name / "cs.comp", kComputeShader);
    write_file(dir_ / "x.json", "{\"Pipelines\": [" + compute_pipeline("P", name + "/cs.comp") + "]}");
    CliRun with = pack("x.json", "-o out.spk --depfile out.d");
    EXPECT_EQ(with.exit_code, 3) << name << "\n" << with.output;
    EXPECT_NE(with.output.find("holds '" + name.substr(1, 1) + "', " + refusal), std::string::npos)
        << with.output;
    EXPECT_FALSE(fs::exists(dir_ / "out.d")) << name;
    // Without a depfile the same pack is fine.
    EXPECT_EQ(pack("x.json", "-o out.spk").exit_code, 0) << name;
    fs::remove(dir_ / "out.spk");
  }
  // The archive's own path is a target of the depfile: a final backslash would escape the separator,
  // and Make reads "lib(m)" as a member of the archive "lib".
  write_file(dir_ / "cs.comp", kComputeShader);
  write_file(dir_ / "y.json", "{\"Pipelines\": [" + compute_pipeline("P", "cs.comp") + "]}");
  for (const std::string& output : {std::string("trail\\"), std::string("lib(m)")}) {
    CliRun with = pack("y.json", "-o '" + output + "' --depfile out.d");
    EXPECT_EQ(with.exit_code, 3) << output << "\n" << with.output;
    EXPECT_NE(with.output.find(refusal), std::string::npos) << with.output;
    EXPECT_FALSE(fs::exists(dir_ / output)) << output;
  }
}

// --- the terminal -------------------------------------------------------------------------------------

TEST_F(HostileInput, InspectNamesWhatItCannotLoadWithoutControlCharacters) {
  const std::string name = "bad\x1b[31m\x07.spk";
  write_file(dir_ / name, "not an archive at all");
  CliRun run = statepack("inspect '" + name + "'");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_EQ(run.output.find('\x1b'), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find('\x07'), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("bad\\x1b[31m\\x07.spk"), std::string::npos) << run.output;
}

}  // namespace
