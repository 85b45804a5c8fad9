// `statepack inspect` on an archive whose names are not valid UTF-8 and hold terminal escapes: JSON
// output replaces invalid bytes with U+FFFD (instead of aborting on nlohmann's type_error 316), and
// text output shows control bytes and invalid UTF-8 as \xNN, so a name cannot drive the terminal; the
// samples' tools escape what they print as well.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/forged_archive.hpp"
#include "common/run_command.hpp"
#include "runtime/archive_access.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::testing {
namespace {

// Each test writes its own copy: ctest -j runs them as concurrent processes, and one truncating the
// file while the other reads it made the reader see 0 bytes.
std::string hostile_names_archive() {
  auto slice = Archive::from_file(STATEPACK_TEST_ARCHIVE);
  EXPECT_TRUE(slice) << slice.error().message;
  format::Contents c = detail::ArchiveAccess::contents(*slice);
  for (auto& p : c.pipelines)
    if (p.name == "Gradient PSO") p.name = "bad\xFFname\x1B[31m";
  for (auto& s : c.shaders)
    if (s.name == "Gradient PS") s.name = "caf\xC3\xA9\x07\\";  // valid UTF-8, a bell, a backslash
  for (auto& l : c.set_layouts)
    for (auto& b : l.bindings)
      if (b.name == "Values") b.name = "half\xE2\x82";  // a truncated three-byte sequence
  const auto bytes = format::encode(c);
  const std::string path = std::string(STATEPACK_TEST_OUTPUT_DIR) + "/hostile_names_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".spk";
  std::filesystem::create_directories(STATEPACK_TEST_OUTPUT_DIR);
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return path;
}

TEST(InspectEscaping, JsonReplacesInvalidUtf8) {
  const std::string path = hostile_names_archive();
  auto result = run_command(std::string(STATEPACK_EXE) + " inspect --json '" + path + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("\"name\": \"bad\xEF\xBF\xBDname\\u001b[31m\""), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("\"name\": \"caf\xC3\xA9\\u0007\\\\\""), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("\"name\": \"half\xEF\xBF\xBD\""), std::string::npos) << result.output;
}

TEST(InspectEscaping, TextEscapesControlsAndInvalidBytes) {
  const std::string path = hostile_names_archive();
  auto result = run_command(std::string(STATEPACK_EXE) + " inspect '" + path + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("pipeline 'bad\\xFFname\\x1B[31m' (graphics)"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("'caf\xC3\xA9\\x07\\x5C'"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("binding 0: 'half\\xE2\\x82' "), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find('\x1B'), std::string::npos);  // no raw escape reaches the terminal
}

#ifdef STATEPACK_UNPACK_DEMO
// The samples' tools print archive names too, through the same escaping (support/printable.hpp):
// unpack_demo lists every pipeline and binding it unpacks, and reports the binding it cannot find.
TEST(InspectEscaping, SampleToolsEscapeWhatTheyPrint) {
  const std::string path = hostile_names_archive();
  auto result = run_command(std::string(STATEPACK_UNPACK_DEMO) + " '" + path + "'");
  EXPECT_NE(result.output.find("unpacked 'bad\\xffname\\x1b[31m' (graphics)"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("binding 0: 'half\\xe2\\x82'"), std::string::npos) << result.output;
  for (char raw : {'\x1B', '\x07', '\xFF'})
    EXPECT_EQ(result.output.find(raw), std::string::npos)
        << "a raw byte " << int(raw) << " reached the terminal";
}
#endif

}  // namespace
}  // namespace statepack::testing
