// Archive loading through the public API: files, content versions, error messages.
#include <gtest/gtest.h>

#include "statepack/dearchiver.hpp"

namespace statepack {
namespace {

TEST(ArchiveLoad, RequiredContentVersionIsChecked) {
  auto ok = Archive::from_file(STATEPACK_TEST_ARCHIVE, 0u);
  ASSERT_TRUE(ok) << ok.error().message;
  auto wrong = Archive::from_file(STATEPACK_TEST_ARCHIVE, 5u);
  ASSERT_FALSE(wrong);
  EXPECT_EQ(wrong.error().code, ErrorCode::content_version_mismatch);
  EXPECT_NE(wrong.error().message.find(STATEPACK_TEST_ARCHIVE), std::string::npos);
}

TEST(ArchiveLoad, MissingFileNamesThePath) {
  auto missing = Archive::from_file("/nonexistent/dir/archive.spk");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, ErrorCode::io_error);
  EXPECT_NE(missing.error().message.find("/nonexistent/dir/archive.spk"), std::string::npos);
}

}  // namespace
}  // namespace statepack
