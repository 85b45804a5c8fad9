// The input stamps' tables hint (packager/pack/input_stamps.hpp): written with the stamps, and handed back
// to a repack only when one of the stamped files no longer stats as stamped (a compile is then likely,
// and glslang's tables are worth building before the notation is read). A damaged entry gives nothing.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <vulkan/vulkan.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/text_files.hpp"
#include "pack/input_stamps.hpp"

namespace statepack::packager {
namespace {

namespace fs = std::filesystem;

class InputStampsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = statepack::testing::fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "input_stamps");
    write("a.comp", "#version 450\nvoid main() {}\n");
    std::string error;
    auto opened = CompileCache::open(dir_ / "cache", uint64_t(1) << 30, error);
    ASSERT_TRUE(opened) << error;
    cache_.emplace(std::move(*opened));
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary | std::ios::trunc) << text;
  }
  InputFile input(const std::string& name) const {
    struct stat st {};
    EXPECT_EQ(::stat((dir_ / name).c_str(), &st), 0);
    return {dir_ / name, {uint64_t(st.st_dev), uint64_t(st.st_ino)}};
  }
  // Stamps `stamped` as a pack that started at `started` would (by default an hour from now: every file
  // older than its racy window), and returns the entry's payload; empty when none was written.
  std::vector<uint8_t> stamp(const StampedInputs& stamped,
                             std::chrono::system_clock::time_point started =
                                 std::chrono::system_clock::now() + std::chrono::hours(1)) {
    EXPECT_EQ(write_input_stamps(*cache_, slot_, stamped, started), "");
    const auto entry = cache_->find_local(stamps_slot(slot_));
    return entry ? std::vector<uint8_t>(entry->payload.begin(), entry->payload.end())
                 : std::vector<uint8_t>{};
  }

  fs::path dir_;
  std::optional<CompileCache> cache_;
  const CacheKey slot_ = KeyBuilder().add("a project").key();
};

TEST_F(InputStampsTest, TheTablesHintComesBackOnlyWhenAStampedFileChanged) {
  const TablesHint hint{SourceLanguage::glsl, VK_SHADER_STAGE_COMPUTE_BIT, 0, "#version 450\n"};
  const std::vector<uint8_t> stamps = stamp({{}, {}, {}, {input("a.comp")}, hint});
  ASSERT_FALSE(stamps.empty());
  EXPECT_EQ(stamped_hint(stamps), hint);             // (read from the head, nothing stat'ed)
  EXPECT_EQ(hint_if_changed(stamps), std::nullopt);  // every file stats as stamped: nothing to compile
  // (Another size: a same-size rewrite within the file system's clock tick could keep every field, which
  // is what the racy window is for.)
  write("a.comp", "#version 460\nvoid main() { }\n");
  EXPECT_EQ(hint_if_changed(stamps), hint);
  fs::remove(dir_ / "a.comp");  // gone: a compile (of whatever takes its place) or an error
  EXPECT_EQ(hint_if_changed(stamps), hint);
  // HLSL: no #version line; the language and stage are what pick the tables.
  write("a.comp", "void main() {}\n");
  const TablesHint hlsl{SourceLanguage::hlsl, VK_SHADER_STAGE_FRAGMENT_BIT, 0, ""};
  const std::vector<uint8_t> hlsl_stamps = stamp({{}, {}, {}, {input("a.comp")}, hlsl});
  write("a.comp", "float4 main() : SV_Target { return 0; }\n");
  EXPECT_EQ(hint_if_changed(hlsl_stamps), hlsl);
}

// A file changed within the racy window of the pack that read it is stamped unsettled: its stamp never
// vouches for it (a second write in the same clock tick could keep every field), yet the entry is written,
// so the pack after the next edit still finds the tables hint. An edit loop packs within seconds of each
// edit: before, such a pack wrote no stamps, and the next one built its tables only after its notation.
TEST_F(InputStampsTest, AFileChangedWithinTheRacyWindowIsStampedUnsettled) {
  const TablesHint hint{SourceLanguage::glsl, VK_SHADER_STAGE_COMPUTE_BIT, 0, "#version 450\n"};
  const auto now = std::chrono::system_clock::now();
  const std::vector<uint8_t> racy = stamp({{}, {}, {}, {input("a.comp")}, hint}, now);
  ASSERT_FALSE(racy.empty());
  EXPECT_EQ(hint_if_changed(racy), hint);  // nothing changed since, but nothing vouches for that
  EXPECT_EQ(unchanged_inputs(*cache_, slot_, {}, {}), std::nullopt);
  // The same file stamped by a pack that began after the window: it vouches, and nothing is to compile.
  const std::vector<uint8_t> settled = stamp({{}, {}, {}, {input("a.comp")}, hint});
  EXPECT_EQ(hint_if_changed(settled), std::nullopt);
  const auto unchanged = unchanged_inputs(*cache_, slot_, {}, {});
  ASSERT_TRUE(unchanged);
  ASSERT_EQ(unchanged->files.size(), 1u);
  EXPECT_EQ(unchanged->files[0].path, dir_ / "a.comp");
}

TEST_F(InputStampsTest, StampsWithoutAHintOrDamagedGiveNone) {
  const std::vector<uint8_t> none = stamp({{}, {}, {}, {input("a.comp")}, std::nullopt});
  ASSERT_FALSE(none.empty());
  write("a.comp", "#version 460\nvoid main() { }\n");
  EXPECT_EQ(stamped_hint(none), std::nullopt);
  EXPECT_EQ(hint_if_changed(none), std::nullopt);
  // A hint no notation makes (no stage, two stages, a GLSLVersion past 4.60, a #version line longer than
  // version_line keeps) is none: these bytes reach glslang.
  for (const TablesHint& odd :
       {TablesHint{SourceLanguage::glsl, 0, 0, ""},
        TablesHint{SourceLanguage::glsl, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, ""},
        TablesHint{SourceLanguage::glsl, VK_SHADER_STAGE_VERTEX_BIT, 470, ""},
        TablesHint{SourceLanguage::glsl, VK_SHADER_STAGE_VERTEX_BIT, 0, std::string(300, 'v')}}) {
    const std::vector<uint8_t> odd_stamps = stamp({{}, {}, {}, {input("a.comp")}, odd});
    EXPECT_EQ(stamped_hint(odd_stamps), std::nullopt);
    write("a.comp", statepack::testing::read_file(dir_ / "a.comp") + " ");
    EXPECT_EQ(hint_if_changed(odd_stamps), std::nullopt);
  }
  const TablesHint hint{SourceLanguage::glsl, VK_SHADER_STAGE_COMPUTE_BIT, 450, "#version 450\n"};
  const std::vector<uint8_t> stamps = stamp({{}, {}, {}, {input("a.comp")}, hint});
  write("a.comp", "#version 450\nvoid main() { }\n");
  ASSERT_EQ(hint_if_changed(stamps), hint);
  // Every prefix of the entry, and every byte flipped: nothing, or the hint itself; never a crash.
  for (size_t size = 0; size < stamps.size(); ++size)
    EXPECT_EQ(hint_if_changed(std::span(stamps.data(), size)), std::nullopt) << size;
  for (size_t size = 0; size < stamps.size(); ++size)  // (the head alone may hold the whole hint)
    if (auto head = stamped_hint(std::span(stamps.data(), size))) {
      EXPECT_EQ(*head, hint) << size;
    }
  for (size_t at = 0; at < stamps.size(); ++at) {
    std::vector<uint8_t> flipped = stamps;
    flipped[at] ^= 0x80;
    const auto got = hint_if_changed(flipped);
    if (got) {
      EXPECT_TRUE(got->language <= SourceLanguage::spirv) << at;
    }
  }
}

}  // namespace
}  // namespace statepack::packager
