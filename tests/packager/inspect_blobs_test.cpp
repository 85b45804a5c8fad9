// `statepack inspect` prints each SPIR-V blob's size and XXH3 content hash: the values must be the ones
// the archive's BLOB table stores, read here straight from the file's bytes (docs/archive-format.md), not
// through the codec inspect itself uses.
#include <gtest/gtest.h>

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "common/forged_archive.hpp"
#include "common/run_command.hpp"
#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

struct StoredBlob {
  uint32_t size = 0;
  uint64_t xxh3 = 0;
};

// The BLOB table of an archive file: {u32 offset, u32 size, u64 xxh3} per blob.
std::vector<StoredBlob> stored_blobs(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  std::vector<StoredBlob> out;
  for (const SectionEntry& s : sections_of(bytes)) {
    if (s.tag != tag_of("BLOB")) continue;
    for (uint32_t i = 0; i < s.count; ++i) {
      const size_t entry = s.offset + 16 * size_t(i);
      out.push_back({get_u32(bytes, entry + 4),
                     uint64_t(get_u32(bytes, entry + 8)) | uint64_t(get_u32(bytes, entry + 12)) << 32});
    }
  }
  return out;
}

std::string hex64(uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016" PRIx64, v);
  return text;
}

TEST(InspectBlobs, TextOutputPrintsTheStoredSizeAndHashOfEveryBlob) {
  std::vector<std::string> archives = corpus_archives();
  archives.push_back(STATEPACK_TEST_ARCHIVE);
  size_t blobs_checked = 0;
  for (const std::string& path : archives) {
    SCOPED_TRACE(path);
    const std::vector<StoredBlob> blobs = stored_blobs(path);
    auto inspect = run_command(std::string(STATEPACK_EXE) + " inspect '" + path + "'");
    ASSERT_EQ(inspect.exit_code, 0) << inspect.output;
    EXPECT_NE(inspect.output.find("\n" + std::to_string(blobs.size()) + " SPIR-V blob(s), "),
              std::string::npos)
        << inspect.output;
    for (size_t i = 0; i < blobs.size(); ++i) {
      const std::string line = "\n  SPIR-V blob " + std::to_string(i) + ": " + std::to_string(blobs[i].size) +
                               " bytes, XXH3 " + hex64(blobs[i].xxh3) + "\n";
      EXPECT_NE(inspect.output.find(line), std::string::npos) << line << "in:\n" << inspect.output;
      ++blobs_checked;
    }
    // No line for a blob the table does not have.
    EXPECT_EQ(inspect.output.find("  SPIR-V blob " + std::to_string(blobs.size()) + ":"), std::string::npos)
        << inspect.output;
  }
  EXPECT_GE(blobs_checked, 10u) << "the archives should hold blobs to compare";
}

}  // namespace
}  // namespace statepack::testing

namespace statepack::testing {
namespace {

// Text inspect shows what an immutable sampler binding bakes in: the binding names its sampler, and the
// sampler's state is listed in the notation's words (POINT filters, WRAP/WRAP/CLAMP addressing).
TEST(InspectText, ImmutableSamplersAreShownWithTheirBinding) {
  auto inspect =
      run_command(std::string(STATEPACK_EXE) + " inspect '" + STATEPACK_IMMUTABLE_SAMPLER_ARCHIVE + "'");
  ASSERT_EQ(inspect.exit_code, 0) << inspect.output;
  EXPECT_NE(inspect.output.find("  sampler 0: filter POINT/POINT/POINT, address WRAP/WRAP/CLAMP, "
                                "anisotropy 0, compare none\n"),
            std::string::npos)
      << inspect.output;
  EXPECT_NE(inspect.output.find("binding 0: 'checker' VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER x1 "
                                "[\"PIXEL\"], immutable sampler 0\n"),
            std::string::npos)
      << inspect.output;
}

}  // namespace
}  // namespace statepack::testing
