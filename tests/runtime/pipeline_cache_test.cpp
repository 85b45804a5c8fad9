// Pipeline caches behind statepack's header: reused on the same device and driver, and ignored with
// a reason when the file comes from another device, another driver, or is damaged.
#include <filesystem>
#include <fstream>

#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

namespace fs = std::filesystem;

class PipelineCache : public VulkanTest {
 protected:
  fs::path path_ = fs::path(STATEPACK_TEST_OUTPUT_DIR) /
                   (std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".cache");

  void save_one() {
    fs::create_directories(path_.parent_path());
    DeviceContext context{vk_->physical_device, vk_->device};
    auto loaded = load_pipeline_cache(context, path_.string() + ".missing");
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_FALSE(loaded->reused);
    EXPECT_NE(loaded->reason.find("no pipeline cache file"), std::string::npos) << loaded->reason;
    context.pipeline_cache = loaded->cache;
    {
      auto dearchiver = Dearchiver::create(context);
      auto archive = Archive::from_file(STATEPACK_TEST_ARCHIVE);
      ASSERT_TRUE(archive);
      ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
      auto all = dearchiver->unpack_all();
      ASSERT_TRUE(all) << all.error().message;
    }
    auto saved = save_pipeline_cache(context, loaded->cache, path_);
    ASSERT_TRUE(saved) << saved.error().message;
    vkDestroyPipelineCache(vk_->device, loaded->cache, nullptr);
  }

  // Loads the file after `edit` changed it; returns the reason it was not reused.
  std::string reload_after(size_t offset, uint8_t value) {
    std::fstream file(path_, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(offset));
    file.put(static_cast<char>(value));
    file.close();
    auto loaded = load_pipeline_cache({vk_->physical_device, vk_->device}, path_);
    EXPECT_TRUE(loaded);
    EXPECT_FALSE(loaded->reused);
    EXPECT_NE(loaded->cache, VK_NULL_HANDLE);  // an empty cache, still usable
    vkDestroyPipelineCache(vk_->device, loaded->cache, nullptr);
    return loaded->reason;
  }
};

TEST_F(PipelineCache, SavedCacheIsReusedOnTheSameDevice) {
  save_one();
  auto loaded = load_pipeline_cache({vk_->physical_device, vk_->device}, path_);
  ASSERT_TRUE(loaded) << loaded.error().message;
  EXPECT_TRUE(loaded->reused) << loaded->reason;
  vkDestroyPipelineCache(vk_->device, loaded->cache, nullptr);
}

TEST_F(PipelineCache, AnotherDeviceIsRejectedWithAMessage) {
  save_one();
  EXPECT_NE(reload_after(16, 0x42).find("another device"), std::string::npos);  // vendorID
}

TEST_F(PipelineCache, AnotherDriverVersionIsRejectedWithAMessage) {
  save_one();
  EXPECT_NE(reload_after(24, 0x77).find("driver version"), std::string::npos);
}

TEST_F(PipelineCache, AnotherDriverBuildIsRejectedWithAMessage) {
  save_one();
  EXPECT_NE(reload_after(64, 0x01).find("driver info"), std::string::npos);  // driver info hash
}

TEST_F(PipelineCache, DamagedDataAndForeignFilesAreRejected) {
  save_one();
  EXPECT_NE(reload_after(fs::file_size(path_) - 1, 0x5A).find("damaged"), std::string::npos);
  EXPECT_NE(reload_after(0, 'X').find("not a statepack pipeline cache"), std::string::npos);
}

}  // namespace
// docs/api.md: io_error is "a file cannot be read or written". A directory, a device or a link where the
// cache (or a variants file) should go is that, named with the reason, and the message says nothing of
// the packer's options.
TEST_F(PipelineCache, AnUnwritablePathIsAnIoErrorNamingIt) {
  const fs::path dir = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "cache_as_directory";
  fs::create_directories(dir);
  const fs::path link = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "cache_link";
  fs::remove(link);
  fs::create_symlink(dir, link);
  DeviceContext context{vk_->physical_device, vk_->device};
  auto loaded = load_pipeline_cache(context, path_.string() + ".missing");
  ASSERT_TRUE(loaded) << loaded.error().message;
  auto dearchiver = Dearchiver::create(context);
  ASSERT_TRUE(dearchiver) << dearchiver.error().message;
  for (const fs::path& target : {dir, link, fs::path("/dev/null")}) {
    auto saved = save_pipeline_cache(context, loaded->cache, target);
    ASSERT_FALSE(saved) << target;
    EXPECT_EQ(saved.error().code, ErrorCode::io_error) << saved.error().message;
    EXPECT_NE(saved.error().message.find("refusing to write '" + target.string() + "'"), std::string::npos)
        << saved.error().message;
    EXPECT_EQ(saved.error().message.find("--check"), std::string::npos) << saved.error().message;
    auto variants = dearchiver->save_variants(target);
    ASSERT_FALSE(variants) << target;
    EXPECT_EQ(variants.error().code, ErrorCode::io_error) << variants.error().message;
  }
  EXPECT_TRUE(fs::is_directory(dir));
  vkDestroyPipelineCache(vk_->device, loaded->cache, nullptr);
}

}  // namespace statepack::testing
