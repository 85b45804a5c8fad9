// What a --watch session keeps from one pack for the next (packager/pack/repack_memo.hpp) is handed back
// only while it holds: a compile while its file and #includes stat as stamped and each #include is found
// where it was, a shader file's text while it stats as stamped; and nothing whose stamp was taken within
// the racy window of the pack that read it. A finalised module needs only the same module.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/time.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/text_files.hpp"
#include "pack/repack_memo.hpp"

namespace statepack::packager {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::system_clock;

class RepackMemoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = statepack::testing::fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "repack_memo");
    write("a.comp", "#version 450\n#include \"common.glsl\"\nvoid main() {}\n");
    write("lib/common.glsl", "const uint k = 1u;\n");
    options_.compile.include_dirs = {dir_ / "lib"};
    unit_.compiled.ok = true;
    unit_.compiled.spirv = {0x07230203u, 0x00010000u};
    unit_.compiled.files_read = {input("a.comp"), input("lib/common.glsl")};
    unit_.compiled.includes = {
        {"common.glsl", (dir_ / "a.comp").string(), true, display_path(dir_ / "lib" / "common.glsl"), {}}};
    texts_[dir_ / "a.comp"] = {input("a.comp"), {}};
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) {
    fs::create_directories((dir_ / name).parent_path());
    std::ofstream(dir_ / name, std::ios::binary | std::ios::trunc) << text;
  }
  InputFile input(const std::string& name) const {
    struct stat st {};
    EXPECT_EQ(::stat((dir_ / name).c_str(), &st), 0);
    return {dir_ / name, {uint64_t(st.st_dev), uint64_t(st.st_ino)}};
  }
  // Keeps the unit, the text and one finalised module as a pack that began at `started` made them.
  void keep(Clock::time_point started) {
    RepackMemo::Made made;
    made.texts = &texts_;
    made.units.push_back({&key_, nullptr, &desc_, &unit_.compiled, &unit_.reflection, &unit_.module});
    made.finalized.push_back({nullptr, &unit_.compiled.spirv, true, &finalized_});
    memo_.keep(made, started, options_.compile);
  }
  bool holds_unit() const { return memo_.unit(key_) != nullptr; }
  bool holds_text() const { return memo_.text(dir_ / "a.comp") != nullptr; }

  // A pack that began an hour from now: every file is older than its racy window.
  const Clock::time_point later_ = Clock::now() + std::chrono::hours(1);
  fs::path dir_;
  PackOptions options_;
  RepackMemo memo_;
  RepackMemo::Unit unit_;
  ShaderDesc desc_;
  std::string key_ = "unit a.comp";
  std::map<fs::path, CompileCache::KnownText> texts_;
  std::vector<uint32_t> finalized_ = {0x07230203u, 0x00010000u, 1u};
};

TEST_F(RepackMemoTest, WhatStillStatsAsStampedIsHandedBack) {
  keep(later_);
  memo_.refresh(options_);
  EXPECT_TRUE(holds_unit());
  EXPECT_TRUE(holds_text());
  ASSERT_NE(memo_.unit(key_), nullptr);
  EXPECT_EQ(memo_.unit(key_)->compiled.spirv, unit_.compiled.spirv);
  EXPECT_EQ(memo_.unit(key_)->entry, compile_entry_key(desc_, options_.compile, unit_.compiled.source_hash));
  // A pack that kept it again: still there, the same entry, not copied again.
  const auto before = memo_.unit(key_);
  RepackMemo::Made again;
  again.units.push_back({&key_, before, &desc_, nullptr, nullptr, nullptr});
  memo_.keep(again, later_, options_.compile);
  memo_.refresh(options_);
  EXPECT_EQ(memo_.unit(key_), before);
}

TEST_F(RepackMemoTest, NothingReadWithinTheRacyWindowIsKept) {
  keep(Clock::now());  // the files were written just now: a second write in the same tick could hide
  memo_.refresh(options_);
  EXPECT_FALSE(holds_unit());
  EXPECT_FALSE(holds_text());
}

TEST_F(RepackMemoTest, AnEditedShaderDropsItsTextAndItsCompile) {
  keep(later_);
  write("a.comp", "#version 450\n#include \"common.glsl\"\nvoid main() { }\n");
  memo_.refresh(options_);
  EXPECT_FALSE(holds_unit());
  EXPECT_FALSE(holds_text());
}

TEST_F(RepackMemoTest, AnEditedIncludeDropsTheCompileButNotTheShadersText) {
  keep(later_);
  write("lib/common.glsl", "const uint k = 2u;\n");
  memo_.refresh(options_);
  EXPECT_FALSE(holds_unit());
  EXPECT_TRUE(holds_text());
}

TEST_F(RepackMemoTest, ATouchedFileCountsAsChanged) {
  keep(later_);
  const timeval times[2] = {{1, 0}, {1, 0}};  // same bytes, another modification time
  ASSERT_EQ(::utimes((dir_ / "a.comp").c_str(), times), 0);
  memo_.refresh(options_);
  EXPECT_FALSE(holds_unit());
}

TEST_F(RepackMemoTest, AnIncludeFoundElsewhereDropsTheCompile) {
  keep(later_);
  write("common.glsl", "const uint k = 3u;\n");  // next to a.comp: found before lib/
  memo_.refresh(options_);
  EXPECT_FALSE(holds_unit());
  EXPECT_TRUE(holds_text());
}

TEST_F(RepackMemoTest, AFinalisedModuleNeedsTheSameModuleAndOptimisation) {
  keep(Clock::now());  // (depends on no file)
  memo_.refresh(options_);
  const auto found = memo_.finalized(unit_.compiled.spirv, true);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->output, finalized_);
  EXPECT_EQ(memo_.finalized(unit_.compiled.spirv, false), nullptr);
  EXPECT_EQ(memo_.finalized({0x07230203u, 0x00010000u, 9u}, true), nullptr);
}

}  // namespace
}  // namespace statepack::packager
