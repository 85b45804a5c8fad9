// statepack pack on input nobody here wrote: every class of hostile notation, shader and command line
// gets a clear error line and an exit code, never a crash, a hang or a lost file. Each test names the
// class it covers and checks the exact message.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "hostile_fixture.hpp"

namespace {

using namespace statepack::testing::hostile;

// --- numbers ----------------------------------------------------------------------------------------

TEST_F(HostileInput, NumberBeyondADoubleIsAnErrorAtItsFirstDigit) {
  write_file(dir_ / "a.json",
             "{\n  \"Pipelines\": [\n    {\"PSODesc\": {\"Name\": \"P\", \"SRBAllocationGranularity\": "
             "1e999}}\n  ]\n}\n");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_EQ(run.output,
            "a.json:3:59: error: number '1e999' is out of range (beyond a double's largest value)\n"
            "statepack: 1 error(s); no archive written\n");
  // Anywhere in the document, also where nothing reads it.
  write_file(dir_ / "b.json", "{\"Ignore\": {\"Signatures\": []}, \"x\": [-1E+999]}");
  EXPECT_NE(pack("b.json").output.find("b.json:1:38: error: number '-1E+999' is out of range"),
            std::string::npos);
}

TEST_F(HostileInput, FloatFieldsRefuseValuesBeyondFloat) {
  write_file(dir_ / "cs.comp", kComputeShader);
  write_file(
      dir_ / "a.json",
      R"({"Pipelines": [{"PSODesc": {"Name": "P"}, "pVS": {"Desc": {"Name": "V", "ShaderType": "VERTEX"}, "Source": "#version 450\nvoid main() {}"},
  "GraphicsPipeline": {"RasterizerDesc": {"DepthBias": 1, "SlopeScaledDepthBias": 1e300, "DepthBiasClamp": -3.5e38}}}]})");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(
      run.output.find("error: 'SlopeScaledDepthBias' must be a finite number within a 32-bit float's range, "
                      "but is 1e+300 [/Pipelines/0/GraphicsPipeline/RasterizerDesc/SlopeScaledDepthBias]"),
      std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find(
                "'DepthBiasClamp' must be a finite number within a 32-bit float's range, but is -3.5e+38"),
            std::string::npos)
      << run.output;
}

TEST_F(HostileInput, NegativeZeroIsZeroInUnsignedFields) {
  write_file(dir_ / "cs.comp", kComputeShader);
  write_file(
      dir_ / "a.json",
      R"({"Pipelines": [{"PSODesc": {"Name": "P", "SRBAllocationGranularity": -0}, "pCS": {"Desc": {"Name": "C", "ShaderType": "COMPUTE"}, "FilePath": "cs.comp"}}]})");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  // A negative number is still refused, with the value named.
  write_file(dir_ / "b.json",
             R"({"Pipelines": [{"PSODesc": {"Name": "P", "SRBAllocationGranularity": -1}}]})");
  EXPECT_NE(pack("b.json").output.find(
                "'SRBAllocationGranularity' must be an integer from 0 to 4294967295, but is -1"),
            std::string::npos);
}

// --- structure --------------------------------------------------------------------------------------

TEST_F(HostileInput, DeepNestingIsRefusedWithItsPlaceNotACrash) {
  const size_t depth = 100000;
  write_file(dir_ / "arrays.json",
             "{\"Pipelines\": " + std::string(depth, '[') + std::string(depth, ']') + "}");
  std::string objects = "{\"Pipelines\": [";
  for (size_t i = 0; i < depth; ++i) objects += "{\"a\":";
  objects += "0" + std::string(depth, '}') + "]}";
  write_file(dir_ / "objects.json", objects);
  CliRun arrays = pack("arrays.json");
  EXPECT_EQ(arrays.exit_code, 1);
  EXPECT_EQ(arrays.output,
            "arrays.json:1:142: error: JSON nested deeper than 128 levels (render-state notation needs fewer "
            "than ten)\nstatepack: 1 error(s); no archive written\n");
  CliRun nested = pack("objects.json");
  EXPECT_EQ(nested.exit_code, 1);
  EXPECT_NE(nested.output.find("objects.json:1:646: error: JSON nested deeper than 128 levels"),
            std::string::npos)
      << nested.output;
  // Brackets inside strings are text, not nesting.
  write_file(dir_ / "strings.json", "{\"Ignore\": {\"Signatures\": [\"" + std::string(1000, '[') + "\"]}}");
  CliRun strings = pack("strings.json", "--check");
  EXPECT_EQ(strings.output.find("nested deeper"), std::string::npos) << strings.output;
  EXPECT_EQ(strings.exit_code, 0) << strings.output;
  EXPECT_NE(strings.output.find("Ignore.Signatures names '[[["), std::string::npos) << strings.output;
}

TEST_F(HostileInput, DuplicateKeysAreErrorsNamingBothPlaces) {
  write_file(dir_ / "a.json", "{\n  \"Pipelines\": [],\n  \"Shaders\": [],\n  \"\\u0050ipelines\": []\n}\n");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(run.output,
            "a.json:4:3: error: duplicate key 'Pipelines' (first at line 2, column 3)\n"
            "statepack: 1 error(s); no archive written\n");
  // Deeper down too, and in every object where it happens.
  write_file(
      dir_ / "b.json",
      R"({"Pipelines": [{"PSODesc": {"Name": "A", "Name": "B"}}, {"PSODesc": {"Name": "C"}, "PSODesc": {}}]})");
  CliRun deeper = pack("b.json");
  EXPECT_NE(deeper.output.find("b.json:1:42: error: duplicate key 'Name' (first at line 1, column 29)"),
            std::string::npos)
      << deeper.output;
  EXPECT_NE(deeper.output.find("b.json:1:84: error: duplicate key 'PSODesc' (first at line 1, column 58)"),
            std::string::npos)
      << deeper.output;
}

TEST_F(HostileInput, ByteOrderMarkDoesNotShiftColumns) {
  write_file(dir_ / "a.json", "\xEF\xBB\xBF{\"Pipelinez\": []}");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.output.substr(0, run.output.find('\n')),
            "a.json:1:2: error: unknown top-level section key 'Pipelinez' (did you mean 'Pipelines'?) "
            "[/Pipelinez]");
}

TEST_F(HostileInput, MillionsOfErrorsStopAtTheLimit) {
  std::string text = "{\"Ignore\": {}";
  for (int i = 0; i < 200000; ++i) text += ",\n\"k" + std::to_string(i) + "\": 0";
  write_file(dir_ / "a.json", text + "}");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(count_lines_with(run.output, ": error: unknown top-level section key"), 100u);
  EXPECT_NE(
      run.output.find("statepack: stopped after 100 errors (--max-errors N sets the limit, 0 for none)\n"),
      std::string::npos)
      << run.output.substr(run.output.size() - 300);
  CliRun five = pack("a.json", "-o out.spk --max-errors 5");
  EXPECT_EQ(count_lines_with(five.output, ": error: "), 5u);
  // Without a limit every one is reported.
  write_file(dir_ / "b.json", "{\"Ignore\": {}, \"x1\": 0, \"x2\": 0, \"x3\": 0}");
  CliRun all = pack("b.json", "-o out.spk --max-errors 0");
  EXPECT_EQ(count_lines_with(all.output, ": error: "), 3u);
}

// "Did you mean" over 200,000 candidate names, for 50,000 unknown references with no error limit, and
// for a name of 100 kB: every message still comes (the work is bounded, tests/support/suggest_test.cpp),
// the early ones with their suggestion; the run takes seconds (it once took minutes).
TEST_F(HostileInput, SuggestionsOverHugeNameSetsStayBounded) {
  std::string text = "{\"Shaders\": [";
  for (int i = 0; i < 200000; ++i)
    text += std::string(i ? "," : "") + R"({"Desc": {"Name": "Shader )" + std::to_string(100000 + i) +
            R"(", "ShaderType": "COMPUTE"}, "FilePath": "a.comp"})";
  text += "], \"Pipelines\": [";
  for (int i = 0; i < 50000; ++i)
    text += std::string(i ? "," : "") + R"({"PSODesc": {"Name": "P)" + std::to_string(i) +
            R"("}, "pCS": "Shader 1000)" + std::to_string(i % 10) + R"(x"})";
  text += R"(, {"PSODesc": {"Name": "Long"}, "pCS": ")" + std::string(100000, 'S') + R"("}]})";
  write_file(dir_ / "a.json", text);
  write_file(dir_ / "a.comp", kComputeShader);
  CliRun run = statepack("pack -i a.json --vulkan -o out.spk --max-errors 0", 120);
  EXPECT_EQ(run.exit_code, 1) << run.output.substr(0, 2000);
  EXPECT_EQ(count_lines_with(run.output, "refers to unknown shader"), 50001u);
  EXPECT_NE(
      run.output.find("pipeline 'P0' refers to unknown shader 'Shader 10000x' (did you mean 'Shader 100000'"),
      std::string::npos)
      << run.output.substr(0, 2000);
}

// A budget against abuse never refuses a large legitimate archive: 100,000 pipelines sharing one
// shader pack, and pack's load-back check (each distinct shader check made once) accepts them.
TEST_F(HostileInput, HundredThousandPipelinesSharingOneShaderPack) {
  std::string text = "{\"Pipelines\": [";
  for (int i = 0; i < 100000; ++i)
    text += std::string(i ? "," : "") + R"({"PSODesc": {"Name": "Compute )" + std::to_string(i) +
            R"("}, "pCS": {"Desc": {"Name": "CS"}, "FilePath": "a.comp"}})";
  write_file(dir_ / "a.json", text + "]}");
  write_file(dir_ / "a.comp", kComputeShader);
  CliRun run = statepack("pack -i a.json --vulkan -o out.spk", 120);
  ASSERT_EQ(run.exit_code, 0) << run.output.substr(0, 2000);
  CliRun inspect = statepack("inspect out.spk --json", 120);
  ASSERT_EQ(inspect.exit_code, 0) << inspect.output.substr(0, 2000);
  EXPECT_NE(inspect.output.find("\"Compute 99999\""), std::string::npos);
}

// Work-group sizes beyond what Vulkan guarantees every device pack with a warning at the shader slot
// (the dearchiver checks the device's own limits; tests/runtime/workgroup_size_test.cpp), with the
// size a specialization constant of the pipeline gives.
TEST_F(HostileInput, WorkGroupSizesBeyondVulkansGuaranteesWarn) {
  write_file(dir_ / "wide.comp",
             "#version 450\nlayout(local_size_x = 256) in;\n"
             "layout(set = 0, binding = 0) buffer Data { uint values[]; } data;\n"
             "void main() { data.values[gl_LocalInvocationIndex] = 1u; }\n");
  write_file(dir_ / "sized.comp",
             "#version 450\nlayout(local_size_x_id = 0, local_size_y = 2) in;\n"
             "layout(constant_id = 0) const uint kX = 1u;\n"
             "layout(set = 0, binding = 0) buffer Data { uint values[]; } data;\n"
             "void main() { data.values[gl_LocalInvocationIndex] = kX; }\n");
  write_file(dir_ / "a.json", "{\"Pipelines\": [" + compute_pipeline("Wide", "wide.comp") + ", " +
                                  compute_pipeline("Small", "sized.comp") + R"(, {"PSODesc": {"Name": "Big"},
      "pCS": {"Desc": {"Name": "Big CS"}, "FilePath": "sized.comp"},
      "pSpecializationConstants": [{"Name": "kX", "Value": 100}]}]})");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(
      run.output.find(
          "a.json:1:53: warning: pipeline 'Wide': shader 'Wide CS' has a work-group size of 256 x 1 x 1, "
          "beyond the maxComputeWorkGroupSize Vulkan guarantees (128, 128, 64): devices with lower "
          "limits refuse the pipeline [/Pipelines/0/pCS]"),
      std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find(
                "warning: pipeline 'Big': shader 'Big CS' has work groups of 100 x 2 x 1 = 200 invocations, "
                "beyond the 128 maxComputeWorkGroupInvocations Vulkan guarantees"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("'Small'"), std::string::npos) << run.output;  // 1 x 2 x 1
}

// The input size limit is an option: each notation file, shader and include, and a shader's includes in
// all, at most --max-input-size bytes (64 MiB by default; suffixes K, M, G). A file over it is an error
// saying how to raise it; raised, the same files pack.
TEST_F(HostileInput, InputSizeLimitIsAnOption) {
  write_file(dir_ / "a.comp", std::string(3000, ' ') + kComputeShader);
  write_file(dir_ / "inc.glsl", std::string(3000, ' ') + "\n");
  write_file(dir_ / "b.comp",
             "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include "
             "\"inc.glsl\"\n#include \"inc.glsl\"\n" +
                 std::string(kComputeShader).substr(13));
  write_file(dir_ / "a.json", "{\"Pipelines\": [" + compute_pipeline("A", "a.comp") + "]}");
  write_file(dir_ / "b.json", "{\"Pipelines\": [" + compute_pipeline("B", "b.comp") + "]}");
  CliRun shader = pack("a.json", "--check --max-input-size 2K");
  EXPECT_EQ(shader.exit_code, 1);
  EXPECT_NE(
      shader.output.find("a.comp: cannot read: " + std::to_string(3000 + std::string(kComputeShader).size()) +
                         " bytes is more than the 2048 bytes allowed (--max-input-size sets the limit)"),
      std::string::npos)
      << shader.output;
  CliRun notation = pack("a.json", "--check --max-input-size 100");
  EXPECT_EQ(notation.exit_code, 1);
  EXPECT_NE(notation.output.find("a.json: cannot read: "), std::string::npos) << notation.output;
  EXPECT_NE(
      notation.output.find(" bytes is more than the 100 bytes allowed (--max-input-size sets the limit)"),
      std::string::npos)
      << notation.output;
  // Each include fits, the two together do not.
  CliRun includes = pack("b.json", "--check --max-input-size 5000");
  EXPECT_EQ(includes.exit_code, 1);
  EXPECT_NE(
      includes.output.find("the includes expand to more than 5000 bytes of source (files included repeatedly "
                           "without include guards?; --max-input-size sets the limit)"),
      std::string::npos)
      << includes.output;
  EXPECT_EQ(pack("a.json", "--check --max-input-size 1M").exit_code, 0);
  EXPECT_EQ(pack("b.json", "--check --max-input-size 1M").exit_code, 0);
  CliRun bad = pack("a.json", "--check --max-input-size 0");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--max-input-size: Value 0 not in range"), std::string::npos) << bad.output;
}

// Pipelines that share a compiled shader (the same file and macros) keep their own shader names and
// places: an interface mismatch in each is reported at that pipeline's own slot, naming its shaders.
TEST_F(HostileInput, PipelinesSharingACompiledShaderAreReportedAtTheirOwnSlots) {
  write_file(dir_ / "a.vert",
             "#version 450\nlayout(location = 0) out vec4 color;\n"
             "void main() { color = vec4(1); gl_Position = vec4(0); }\n");
  write_file(dir_ / "a.frag",
             "#version 450\nlayout(location = 0) flat in ivec4 color;\nlayout(location = 0) out vec4 outc;\n"
             "void main() { outc = vec4(color); }\n");
  std::string pipelines;
  for (const char* n : {"1", "2"})
    pipelines +=
        std::string(*n == '1' ? "" : ",\n") + R"({"PSODesc": {"Name": "P)" + n +
        R"("}, "GraphicsPipeline": {"RTVFormats": {"0": "RGBA8_UNORM"}}, "pVS": {"Desc": {"Name": "VS)" + n +
        R"("}, "FilePath": "a.vert"}, "pPS": {"Desc": {"Name": "PS)" + n + R"("}, "FilePath": "a.frag"}})";
  write_file(dir_ / "a.json", "{\"Pipelines\": [\n" + pipelines + "]}");
  CliRun run = pack("a.json", "--check");
  EXPECT_EQ(run.exit_code, 1);
  for (const char* n : {"1", "2"}) {
    const std::string line = std::string(n) == "1" ? "2" : "3", index = std::string(n) == "1" ? "0" : "1";
    EXPECT_NE(
        run.output.find("a.json:" + line + ":150: error: pipeline 'P" + n + "': pixel shader 'PS" + n +
                        "' reads 'flat ivec4 color' at location 0 as signed integer, but vertex shader 'VS" +
                        n + "' writes 'vec4 color' there as float [/Pipelines/" + index + "/pPS]"),
        std::string::npos)
        << run.output;
  }
}

// --- shaders and includes ---------------------------------------------------------------------------

TEST_F(HostileInput, IncludeCyclesAreReportedWithTheirChain) {
  const std::string ext = "#extension GL_GOOGLE_include_directive : require\n";
  write_file(dir_ / "a.glsl", "#include \"b.glsl\"\n");
  write_file(dir_ / "b.glsl", "#include \"a.glsl\"\n");
  write_file(dir_ / "cycle.comp",
             "#version 450\n" + ext + "#include \"a.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n");
  write_file(dir_ / "self.comp", "#version 450\n" + ext + "#include \"self.comp\"\nvoid main() {}\n");
  write_file(dir_ / "a.json", "{\"Pipelines\": [\n" + compute_pipeline("Cycle", "cycle.comp") + ",\n" +
                                  compute_pipeline("Self", "self.comp") + "]}");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(run.output,
            // At the #include that closes the cycle.
            "b.glsl:1: error: shader 'Cycle CS': #include cycle: a.glsl -> b.glsl -> a.glsl\n"
            "self.comp:3: error: shader 'Self CS': #include cycle: self.comp -> self.comp\n"
            "statepack: 2 error(s); no archive written\n");
}

// One mistake, one error, said first: glslang's follow-on messages (an unknown #extension's "extra
// tokens", an error inside #if leaving "missing #endif", "Could not process include directive") give way
// to the cause; an #endif really missing is still said.
TEST_F(HostileInput, ShaderMistakesGiveOneErrorEachWithTheCause) {
  write_file(dir_ / "extension.comp",
             "#version 450\n#extension GL_FOO_bar : require\nlayout(local_size_x = 1) in;\nvoid main() {}\n");
  write_file(dir_ / "inside_if.comp",
             "#version 450\nlayout(local_size_x = 1) in;\nvoid main() {\n#if 1\n  undefined_thing = "
             "1;\n#endif\n}\n");
  write_file(dir_ / "no_endif.comp", "#version 450\nlayout(local_size_x = 1) in;\n#if 1\nvoid main() {}\n");
  write_file(dir_ / "missing.comp",
             "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
             "#include \"nowhere.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n");
  write_file(dir_ / "a.json", "{\"Pipelines\": [\n" + compute_pipeline("Extension", "extension.comp") +
                                  ",\n" + compute_pipeline("Inside If", "inside_if.comp") + ",\n" +
                                  compute_pipeline("No Endif", "no_endif.comp") + ",\n" +
                                  compute_pipeline("Missing", "missing.comp") + "]}");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(
      run.output,
      "extension.comp:2: error: shader 'Extension CS': '#extension' : extension not supported: GL_FOO_bar\n"
      "inside_if.comp:5: error: shader 'Inside If CS': 'undefined_thing' : undeclared identifier\n"
      "missing.comp:3: error: shader 'Missing CS': #include \"nowhere.glsl\": no such file next to "
      "missing.comp (no -s directory given)\n"
      "no_endif.comp:5: error: shader 'No Endif CS': '' : missing #endif\n"
      "statepack: 4 error(s); no archive written\n");
}

// The OpenGL compile of a source is named as every OpenGL message names it: 'X' (OpenGL).
TEST_F(HostileInput, OpenGlCompileErrorsNameTheShaderAsOtherOpenGlMessages) {
  write_file(
      dir_ / "guarded.comp",
      "#version 450\nlayout(local_size_x = 1) in;\nlayout(set = 0, binding = 0) buffer B { uint v[]; };\n"
      "void main() {\n#ifdef VULKAN\n  v[0] = 1u;\n#else\n  v[0] = undefined_thing;\n#endif\n}\n");
  write_file(dir_ / "a.json", "{\"Pipelines\": [" + compute_pipeline("Guarded", "guarded.comp") + "]}");
  CliRun run = pack("a.json", "--opengl -o out.spk");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(run.output,
            "guarded.comp:8: error: shader 'Guarded CS' (OpenGL): 'undefined_thing' : undeclared identifier\n"
            "statepack: 1 error(s); no archive written\n");
}

TEST_F(HostileInput, IncludesThatExpandExponentiallyAreStopped) {
  // l0 includes l1 twice, l1 includes l2 twice, ...: 2^40 copies without a limit.
  for (int i = 0; i < 40; ++i)
    write_file(dir_ / ("l" + std::to_string(i) + ".glsl"),
               std::string(1000, ' ') + "\n#include \"l" + std::to_string(i + 1) + ".glsl\"\n#include \"l" +
                   std::to_string(i + 1) + ".glsl\"\n");
  write_file(dir_ / "l40.glsl", "\n");
  write_file(dir_ / "boom.comp",
             "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
             "#include \"l0.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n");
  write_file(dir_ / "a.json", "{\"Pipelines\": [" + compute_pipeline("Boom", "boom.comp") + "]}");
  auto start = std::chrono::steady_clock::now();
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("error: shader 'Boom CS': #include \"l"), std::string::npos) << run.output;
  EXPECT_NE(
      run.output.find("the includes expand to more than 64 MiB of source (files included repeatedly without "
                      "include guards?; --max-input-size sets the limit)"),
      std::string::npos)
      << run.output;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(50));
}

TEST_F(HostileInput, OneShaderFailingToCompileDoesNotHideOtherPipelinesErrors) {
  write_file(dir_ / "broken.comp",
             "#version 450\nlayout(local_size_x = 1) in;\nvoid main() { undefined_name = 1; }\n");
  write_file(dir_ / "cs.comp", kComputeShader);
  write_file(
      dir_ / "a.json",
      R"({"ResourceSignatures": [{"Name": "Empty", "Resources": [{"Name": "other", "ShaderStages": "COMPUTE", "ResourceType": "BUFFER_UAV"}]}],
"Pipelines": [)" +
          compute_pipeline("Broken", "broken.comp") +
          R"(,
{"PSODesc": {"Name": "Mismatch"}, "ppResourceSignatures": ["Empty"], "pCS": {"Desc": {"Name": "Mismatch CS", "ShaderType": "COMPUTE"}, "FilePath": "cs.comp"}}]})");
  CliRun run = pack("a.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(
      run.output.find("broken.comp:3: error: shader 'Broken CS': 'undefined_name' : undeclared identifier"),
      std::string::npos)
      << run.output;
  EXPECT_NE(
      run.output.find("error: pipeline 'Mismatch', shader 'Mismatch CS': resource 'Data' is in none of the "
                      "pipeline's resource signatures"),
      std::string::npos)
      << run.output;
}

// --- reading files ----------------------------------------------------------------------------------

TEST_F(HostileInput, NonRegularInputsAreRefusedWithoutBlocking) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo.json").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir_ / "fifo.comp").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir_ / "fifo.glsl").c_str(), 0600), 0);
  fs::create_directories(dir_ / "dir.comp");
  CliRun fifo = pack("fifo.json");
  EXPECT_EQ(fifo.exit_code, 1);
  EXPECT_NE(fifo.output.find("statepack: error: fifo.json: cannot read: it is a FIFO, not a regular file\n"),
            std::string::npos)
      << fifo.output;
  write_file(dir_ / "inc.comp",
             "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"fifo.glsl\"\nvoid "
             "main() {}\n");
  write_file(dir_ / "a.json", "{\"Pipelines\": [" + compute_pipeline("F", "fifo.comp") + ",\n" +
                                  compute_pipeline("D", "dir.comp") + ",\n" +
                                  compute_pipeline("I", "inc.comp") + "]}");
  CliRun shaders = pack("a.json");
  EXPECT_EQ(shaders.exit_code, 1);
  EXPECT_NE(
      shaders.output.find("error: shader 'F CS': fifo.comp: cannot read: it is a FIFO, not a regular file"),
      std::string::npos)
      << shaders.output;
  EXPECT_NE(shaders.output.find(
                "error: shader 'D CS': dir.comp: cannot read: it is a directory, not a regular file"),
            std::string::npos)
      << shaders.output;
  EXPECT_NE(shaders.output.find(
                "error: shader 'I CS': #include \"fifo.glsl\": fifo.glsl: cannot read: it is a FIFO"),
            std::string::npos)
      << shaders.output;
  // A directory named as the input, and a file too large to be notation.
  CliRun directory = pack(".");
  EXPECT_NE(directory.output.find("statepack: error: .: cannot read: it is a directory, not a regular file"),
            std::string::npos)
      << directory.output;
  { std::ofstream(dir_ / "huge.json"); }
  fs::resize_file(dir_ / "huge.json", (64ull << 20) + 1);  // sparse: costs no disk
  CliRun huge = pack("huge.json");
  EXPECT_NE(
      huge.output.find("huge.json: cannot read: 67108865 bytes is more than the 67108864 bytes allowed"),
      std::string::npos)
      << huge.output;
}

// --- writing files ----------------------------------------------------------------------------------

TEST_F(HostileOutput, NoOutputReplacesAnInputHoweverItIsSpelled) {
  const std::string cwd = dir_.string();
  const std::pair<std::string, std::string> cases[] = {
      {"-o a.json", "refusing to write 'a.json': it is the input '" + cwd + "/a.json' of this run"},
      {"-o ./inc/../a.json", "refusing to write './inc/../a.json': it is the input '" + cwd + "/a.json'"},
      {"-o '" + cwd + "/base.json'", "it is the input '" + cwd + "/base.json' of this run"},
      {"-o cs.comp", "refusing to write 'cs.comp': it is the input '" + cwd + "/cs.comp' of this run"},
      {"-o inc/common.glsl",
       "refusing to write 'inc/common.glsl': it is the input '" + cwd + "/inc/common.glsl'"},
      {"-o out.spk --depfile base.json",
       "refusing to write 'base.json': it is the input '" + cwd + "/base.json'"},
      {"-o out.spk --depfile out.spk", "refusing to write 'out.spk': it is also the output 'out.spk'"},
  };
  for (const auto& [args, message] : cases) {
    CliRun run = pack("a.json", args);
    EXPECT_EQ(run.exit_code, 2) << args << "\n" << run.output;
    EXPECT_NE(run.output.find(message), std::string::npos) << args << "\n" << run.output;
    expect_inputs_unchanged();
  }
  // A hard link to an input is that input.
  fs::create_hard_link(dir_ / "cs.comp", dir_ / "hard.spk");
  CliRun hard = pack("a.json", "-o hard.spk");
  EXPECT_EQ(hard.exit_code, 2);
  EXPECT_NE(
      hard.output.find("refusing to write 'hard.spk': it is the input '" + cwd + "/cs.comp' of this run"),
      std::string::npos)
      << hard.output;
  // A symlink is refused whatever it points to: renaming over it would replace the link, not its target.
  fs::create_symlink("cs.comp", dir_ / "link.spk");
  CliRun link = pack("a.json", "-o link.spk");
  EXPECT_EQ(link.exit_code, 2);
  EXPECT_NE(link.output.find("refusing to write 'link.spk': it is a symbolic link"), std::string::npos)
      << link.output;
  // --dump_dir files are outputs too.
  fs::create_directories(dir_ / "dump" / "Vulkan" / "compute" / "P");
  fs::create_hard_link(dir_ / "base.json", dir_ / "dump" / "Vulkan" / "compute" / "P" / "P CS.spv");
  CliRun dump = pack("a.json", "-o out.spk -d dump");
  EXPECT_EQ(dump.exit_code, 3) << dump.output;
  EXPECT_NE(dump.output.find("it is the input '" + cwd + "/base.json' of this run"), std::string::npos)
      << dump.output;
  expect_inputs_unchanged();
}

TEST_F(HostileOutput, NonRegularOutputsAreRefusedAndCheckWritesNothing) {
  CliRun null = pack("a.json", "-o /dev/null");
  EXPECT_EQ(null.exit_code, 2);
  EXPECT_EQ(null.output,
            "statepack: error: refusing to write '/dev/null': it is a character device, and outputs must be "
            "regular "
            "files (use --check to pack without writing)\n");
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  ASSERT_EQ(::mkfifo((dir_ / "fifo.spk").c_str(), 0600), 0);
  EXPECT_NE(pack("a.json", "-o fifo.spk").output.find("'fifo.spk': it is a FIFO"), std::string::npos);
  EXPECT_NE(pack("a.json", "-o inc").output.find("'inc': it is a directory"), std::string::npos);
  CliRun check = pack("a.json", "--check");
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_FALSE(fs::exists(dir_ / "out.spk"));
  EXPECT_EQ(pack("a.json", "--check -o out.spk").exit_code, 2);
  EXPECT_EQ(statepack("pack -i a.json --vulkan").exit_code, 2);
}

TEST_F(HostileOutput, ArchiveAndDepfileAreAllOrNothing) {
  ASSERT_EQ(pack("a.json", "-o out.spk --depfile out.d").exit_code, 0);
  const std::string archive = read_file(dir_ / "out.spk"), depfile = read_file(dir_ / "out.d");
  // Change an input, then fail on the depfile: the old archive must stay, matching the old depfile.
  write_file(dir_ / "inc" / "common.glsl", "const uint kValue = 8u;\n");
  CliRun run = pack("a.json", "-o out.spk --depfile missing/out.d");
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_EQ(run.output, "statepack: error: cannot create 'missing/out.d': No such file or directory\n");
  EXPECT_EQ(read_file(dir_ / "out.spk"), archive);
  EXPECT_EQ(read_file(dir_ / "out.d"), depfile);
  // I/O failures name the OS's reason.
  CliRun not_dir = pack("a.json", "-o a.json/out.spk");
  EXPECT_EQ(not_dir.exit_code, 3);
  EXPECT_EQ(not_dir.output, "statepack: error: cannot create 'a.json/out.spk': Not a directory\n");
  // Nothing is left beside the outputs.
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find("statepack-tmp"), std::string::npos) << entry.path();
}

TEST_F(HostileOutput, TemporariesOfKilledRunsAreCleanedUp) {
  // A process that no longer exists (PIDs never reach this), and one that does (this test).
  const fs::path stale = dir_ / ".out.spk.statepack-tmp-2147483600-0";
  const fs::path live = dir_ / (".out.spk.statepack-tmp-" + std::to_string(::getpid()) + "-0");
  write_file(stale, "half an archive");
  write_file(live, "someone else's");
  ASSERT_EQ(pack("a.json", "-o out.spk").exit_code, 0);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
}

TEST_F(HostileOutput, NamesAreEscapedBeforeTheyReachTheTerminalOrTheDepfile) {
  write_file(dir_ / "b.json", "{\"Pipelines\": [{\"PSODesc\": {\"Name\": \"\\u001b[31mred\\u0007\"}}]}");
  CliRun run = pack("b.json");
  EXPECT_EQ(run.output.find('\x1b'), std::string::npos);
  EXPECT_EQ(run.output.find('\x07'), std::string::npos);
  EXPECT_NE(run.output.find("pipeline '\\x1b[31mred\\x07' has no shaders"), std::string::npos) << run.output;
  // A path with a newline cannot be written in Make syntax: an error, not a broken depfile.
  fs::create_directories(dir_ / "new\nline");
  CliRun newline = pack("a.json", "-o 'new\nline/out.spk' --depfile out.d");
  EXPECT_EQ(newline.exit_code, 3);
  EXPECT_NE(newline.output.find(
                "cannot write the depfile: the path 'new\\x0aline/out.spk' holds a control character"),
            std::string::npos)
      << newline.output;
  EXPECT_FALSE(fs::exists(dir_ / "out.d"));
  // Spaces, '#' and '$' are escaped as Make reads them.
  write_file(dir_ / "odd dir #1" / "cs$.comp", read_file(dir_ / "cs.comp"));
  fs::create_directories(dir_ / "odd dir #1" / "inc");
  write_file(dir_ / "odd dir #1" / "inc" / "common.glsl", "const uint kValue = 7u;\n");
  write_file(dir_ / "c.json", "{\"Pipelines\": [" + compute_pipeline("P", "odd dir #1/cs$.comp") + "]}");
  ASSERT_EQ(pack("c.json", "-o out.spk --depfile odd.d").exit_code, 0);
  EXPECT_NE(read_file(dir_ / "odd.d").find("odd\\ dir\\ \\#1/cs$$.comp"), std::string::npos)
      << read_file(dir_ / "odd.d");
}

}  // namespace
