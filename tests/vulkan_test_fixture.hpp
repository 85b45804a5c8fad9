// GoogleTest fixture for every Vulkan test: lavapipe only, validation layer on, and any validation
// warning or error fails the test that caused it.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "statepack/dearchiver.hpp"
#include "vulkan_context.hpp"

namespace statepack::testing {

// The archives built from tests/corpus/valid (their paths come from CMake, '|'-separated).
inline std::vector<std::string> corpus_archives() {
  std::vector<std::string> out;
  std::istringstream list(STATEPACK_CORPUS_ARCHIVES);
  for (std::string path; std::getline(list, path, '|');)
    if (!path.empty()) out.push_back(path);
  return out;
}

class VulkanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    samples::VulkanContextOptions options;
    options.validation = true;
    options.require_lavapipe = true;
    auto created = samples::VulkanContext::create(options);
    ASSERT_TRUE(created) << created.error().message;
    vk_ = std::move(created.value());
  }

  void TearDown() override {
    if (!vk_) return;
    vk_->destroy_device();  // the layer reports Vulkan objects the test (or the dearchiver) leaked
    for (const auto& message : vk_->validation_messages()) ADD_FAILURE() << message;
  }

  // A dearchiver with the test archive loaded (built by statepack_add_archive in tests/CMakeLists.txt).
  Dearchiver make_dearchiver() {
    auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
    EXPECT_TRUE(dearchiver) << dearchiver.error().message;
    auto archive = Archive::from_file(STATEPACK_TEST_ARCHIVE);
    EXPECT_TRUE(archive) << archive.error().message;
    auto added = dearchiver->add_archive(std::move(archive.value()));
    EXPECT_TRUE(added);
    return std::move(dearchiver.value());
  }

  std::unique_ptr<samples::VulkanContext> vk_;
};

}  // namespace statepack::testing
