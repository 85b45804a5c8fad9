// gl::Dearchiver::reload on llvmpipe: a temporary project packed for both backends by the real packer,
// edited and packed again; the same Program runs the new shader, an unchanged one keeps its GL program,
// a change of bindings keeps the old program and says why.
#include <epoxy/gl.h>

#include <filesystem>
#include <fstream>

#include "common/run_command.hpp"
#include "common/text_files.hpp"
#include "gl_test_fixture.hpp"
#include "statepack/gl_dearchiver.hpp"

namespace statepack::testing {
namespace {

namespace fs = std::filesystem;

std::string writer(const std::string& value, const std::string& extra = "") {
  return "#version 450\nlayout(local_size_x = 1) in;\n"
         "layout(std430, binding = 0) buffer Result { uint value; } result;\n" +
         extra + "void main() { result.value = " + value + "; }\n";
}

class GlReloadTest : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    dir_ = fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "gl_reload");
    write("states.json", R"({ "Pipelines": [
      { "PSODesc": { "Name": "A" }, "pCS": { "Desc": { "Name": "A CS" }, "FilePath": "a.comp" } },
      { "PSODesc": { "Name": "B" }, "pCS": { "Desc": { "Name": "B CS" }, "FilePath": "b.comp" } } ] })");
  }
  void write(const std::string& file, const std::string& text) { write_file(dir_ / file, text); }
  Archive pack() {
    const fs::path out = dir_ / "out.spk";
    CommandResult r = run_command("'" STATEPACK_EXE "' pack --vulkan --opengl -s '" + dir_.string() +
                                  "' -o '" + out.string() + "' -i '" + (dir_ / "states.json").string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    auto archive = Archive::from_file(out);
    EXPECT_TRUE(archive) << archive.error().message;
    return std::move(*archive);
  }
  // Dispatches the program once; what it wrote.
  static uint32_t run(const gl::Program& program) {
    const gl::Binding* result = program.find_binding("Result");
    EXPECT_NE(result, nullptr);
    if (!result) return ~0u;
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    const uint32_t initial = 0xEEEEEEEEu;
    glNamedBufferStorage(buffer, sizeof initial, &initial, GL_MAP_READ_BIT);
    glUseProgram(program.program);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, result->binding, buffer);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    uint32_t value = 0;
    glGetNamedBufferSubData(buffer, 0, sizeof value, &value);
    glUseProgram(0);
    glDeleteBuffers(1, &buffer);
    return value;
  }
  fs::path dir_;
};

TEST_F(GlReloadTest, AnEditedShaderRunsInTheSameProgramAndAnUnchangedOneKeepsItsName) {
  write("a.comp", writer("10u"));
  write("b.comp", writer("20u"));
  gl::Dearchiver d = make_gl_dearchiver(pack());
  auto a = d.unpack_compute("A");
  auto b = d.unpack_compute("B");
  ASSERT_TRUE(a && b);
  EXPECT_EQ(run(**a), 10u);
  const GLuint b_before = (*b)->program;

  write("a.comp", writer("30u"));
  auto report = d.reload(pack());
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_TRUE(report->ok());
  EXPECT_EQ(report->recreated, std::vector<std::string>{"A"});
  EXPECT_EQ(report->kept, std::vector<std::string>{"B"});
  EXPECT_EQ(report->generation, 1u);
  EXPECT_EQ(run(**a), 30u);
  EXPECT_EQ((*b)->program, b_before);
  EXPECT_EQ(run(**b), 20u);
  EXPECT_EQ(d.destroy_retired(), 1u);

  // A change of bindings: refused, the old program stays, and the next good build is taken.
  write("a.comp", writer("40u + more.x", "layout(std430, binding = 1) buffer More { uint x; } more;\n"));
  auto refused = d.reload(pack());
  ASSERT_TRUE(refused) << refused.error().message;
  ASSERT_EQ(refused->failures.size(), 1u);
  EXPECT_EQ(refused->failures[0].error.code, ErrorCode::layout_changed);
  EXPECT_NE(refused->failures[0].error.message.find("pipeline 'A'"), std::string::npos);
  EXPECT_EQ(run(**a), 30u);
  write("a.comp", writer("50u"));
  auto fixed = d.reload(pack());
  ASSERT_TRUE(fixed) << fixed.error().message;
  EXPECT_EQ(fixed->recreated, std::vector<std::string>{"A"});
  EXPECT_EQ(run(**a), 50u);
}

TEST_F(GlReloadTest, ARemovedPipelineStaysTheApplicationsAndIsNoLongerFoundByName) {
  write("a.comp", writer("1u"));
  write("b.comp", writer("2u"));
  gl::Dearchiver d = make_gl_dearchiver(pack());
  auto b = d.unpack_compute("B");
  ASSERT_TRUE(b);
  write("states.json", R"({ "Pipelines": [
      { "PSODesc": { "Name": "A" }, "pCS": { "Desc": { "Name": "A CS" }, "FilePath": "a.comp" } },
      { "PSODesc": { "Name": "C" }, "pCS": { "Desc": { "Name": "B CS" }, "FilePath": "b.comp" } } ] })");
  auto report = d.reload(pack());
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_EQ(report->removed, std::vector<std::string>{"B"});
  EXPECT_EQ(report->added, std::vector<std::string>{"C"});
  EXPECT_EQ(run(**b), 2u);
  EXPECT_FALSE(d.unpack_compute("B"));
  auto c = d.unpack_compute("C");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(run(**c), 2u);
}

}  // namespace
}  // namespace statepack::testing
