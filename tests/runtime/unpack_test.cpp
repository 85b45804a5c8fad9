// Dearchiver behaviour beyond the slice: unpacking everything on several threads, names across
// several archives, device features, and missing backends.
#include <cstring>
#include <set>
#include <sstream>

#include "common/vulkan_test_fixture.hpp"
#include "format/archive_format.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

// Re-encodes a modified copy of an archive's contents into aligned memory.
struct ForgedArchive {
  std::vector<uint32_t> words;
  size_t size = 0;
  explicit ForgedArchive(const format::Contents& contents) {
    auto bytes = format::encode(contents);
    size = bytes.size();
    words.resize((size + 3) / 4);
    std::memcpy(words.data(), bytes.data(), size);
  }
  std::span<const uint8_t> span() const { return {reinterpret_cast<const uint8_t*>(words.data()), size}; }
};

class Unpack : public VulkanTest {};

TEST_F(Unpack, EverythingOnSeveralThreadsMatchesOneByOne) {
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver);
  std::set<std::string> expected;
  for (const auto& path : corpus_archives_without_run_time_state()) {
    auto archive = Archive::from_file(path);
    ASSERT_TRUE(archive) << archive.error().message;
    for (const auto& o : archive->objects())
      if (o.kind == ObjectKind::graphics_pipeline || o.kind == ObjectKind::compute_pipeline)
        expected.insert(o.name);
    ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  }
  auto one = dearchiver->unpack_compute("Blur PSO");  // already unpacked ones are reused
  ASSERT_TRUE(one) << one.error().message;
  auto all = dearchiver->unpack_all(4);
  ASSERT_TRUE(all) << all.error().message;
  std::set<std::string> names;
  for (const UnpackedPipeline* p : *all) {
    EXPECT_NE(p->pipeline, VK_NULL_HANDLE) << p->name;
    names.insert(p->name);
  }
  EXPECT_EQ(names, expected);
  EXPECT_NE(std::find(all->begin(), all->end(), *one), all->end());
  // A second call creates nothing new.
  auto again = dearchiver->unpack_all(2);
  ASSERT_TRUE(again);
  EXPECT_EQ(std::set<const UnpackedPipeline*>(again->begin(), again->end()),
            std::set<const UnpackedPipeline*>(all->begin(), all->end()));
}

TEST_F(Unpack, NamesResolveAcrossArchivesAndTheFirstWins) {
  auto first = Archive::from_file(STATEPACK_TEST_ARCHIVE);
  ASSERT_TRUE(first);
  format::Contents renamed = detail::ArchiveAccess::contents(*first);
  for (auto& p : renamed.pipelines)
    if (p.name == "Fill Buffer PSO") p.name = "Only In Second";
  ForgedArchive second_bytes(renamed);
  auto second = Archive::from_memory(second_bytes.span());
  ASSERT_TRUE(second) << second.error().message;
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver->add_archive(std::move(*first)));
  ASSERT_TRUE(dearchiver->add_archive(std::move(*second)));
  auto from_second = dearchiver->unpack_compute("Only In Second");
  ASSERT_TRUE(from_second) << from_second.error().message;
  auto shared = dearchiver->unpack_graphics("Gradient PSO");
  ASSERT_TRUE(shared);
  // Both archives hold "Gradient PSO"; the first added one is used, and unpack_all keeps one of each.
  auto all = dearchiver->unpack_all();
  ASSERT_TRUE(all) << all.error().message;
  EXPECT_EQ(all->size(), 3u);
}

TEST_F(Unpack, PipelineNeedingADisabledFeatureIsAnError) {
  auto archive = Archive::from_file(STATEPACK_TEST_ARCHIVE);
  ASSERT_TRUE(archive);
  format::Contents wireframe = detail::ArchiveAccess::contents(*archive);
  for (auto& p : wireframe.pipelines) p.graphics.polygon_mode = VK_POLYGON_MODE_LINE;
  ForgedArchive bytes(wireframe);
  auto forged = Archive::from_memory(bytes.span());
  ASSERT_TRUE(forged) << forged.error().message;
  VkPhysicalDeviceFeatures none{};  // the fixture's device enables no core features
  DeviceContext context{vk_->physical_device, vk_->device};
  context.enabled_features = &none;
  auto dearchiver = Dearchiver::create(context);
  ASSERT_TRUE(dearchiver->add_archive(std::move(*forged)));
  auto pso = dearchiver->unpack_graphics("Gradient PSO");
  ASSERT_FALSE(pso);
  EXPECT_EQ(pso.error().code, ErrorCode::unsupported);
  EXPECT_NE(pso.error().message.find("fillModeNonSolid"), std::string::npos) << pso.error().message;
}

TEST_F(Unpack, ArchiveWithoutVulkanDataIsAnError) {
  auto archive = Archive::from_file(STATEPACK_TEST_ARCHIVE);
  ASSERT_TRUE(archive);
  format::Contents other = detail::ArchiveAccess::contents(*archive);
  other.backends = format::kBackendOpenGL;
  ForgedArchive bytes(other);
  auto forged = Archive::from_memory(bytes.span());
  ASSERT_TRUE(forged);
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver->add_archive(std::move(*forged)));
  auto pso = dearchiver->unpack_compute("Fill Buffer PSO");
  ASSERT_FALSE(pso);
  EXPECT_EQ(pso.error().code, ErrorCode::missing_backend);
}

TEST_F(Unpack, InvalidCreateArgumentsAreErrors) {
  auto missing = Dearchiver::create({});
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, ErrorCode::invalid_argument);
}

// The application owns dispatch: every entry point comes through the functions it gives. A table that
// wraps vkCreateComputePipelines sees the dearchiver's call; one that lacks a function is refused at
// create, naming the function; a get_instance_proc_addr without its instance is refused.
namespace app_dispatch {
PFN_vkGetDeviceProcAddr real_device_proc_addr = nullptr;
PFN_vkCreateComputePipelines real_create_compute = nullptr;
int compute_creates = 0;
const char* withheld = nullptr;
VKAPI_ATTR VkResult VKAPI_CALL counting_create_compute(VkDevice device, VkPipelineCache cache, uint32_t count,
                                                       const VkComputePipelineCreateInfo* infos,
                                                       const VkAllocationCallbacks* allocator,
                                                       VkPipeline* pipelines) {
  ++compute_creates;
  return real_create_compute(device, cache, count, infos, allocator, pipelines);
}
VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL device_proc_addr(VkDevice device, const char* name) {
  if (withheld && std::strcmp(name, withheld) == 0) return nullptr;
  if (std::strcmp(name, "vkCreateComputePipelines") == 0) {
    real_create_compute = reinterpret_cast<PFN_vkCreateComputePipelines>(real_device_proc_addr(device, name));
    return reinterpret_cast<PFN_vkVoidFunction>(&counting_create_compute);
  }
  return real_device_proc_addr(device, name);
}
}  // namespace app_dispatch

TEST_F(Unpack, TheApplicationsDispatchIsTheOneUsed) {
  DeviceContext context = vk_->device_context();
  app_dispatch::real_device_proc_addr =
      reinterpret_cast<PFN_vkGetDeviceProcAddr>(vkGetInstanceProcAddr(vk_->instance, "vkGetDeviceProcAddr"));
  context.get_device_proc_addr = &app_dispatch::device_proc_addr;
  app_dispatch::compute_creates = 0;
  app_dispatch::withheld = nullptr;
  {
    auto dearchiver = Dearchiver::create(context);
    ASSERT_TRUE(dearchiver) << dearchiver.error().message;
    ASSERT_TRUE(dearchiver->add_archive(Archive::from_file(STATEPACK_TEST_ARCHIVE).value()));
    auto pso = dearchiver->unpack_compute("Fill Buffer PSO");
    ASSERT_TRUE(pso) << pso.error().message;
    EXPECT_NE((*pso)->pipeline, VK_NULL_HANDLE);
  }
  EXPECT_EQ(app_dispatch::compute_creates, 1);

  app_dispatch::withheld = "vkCreateGraphicsPipelines";
  auto lacking = Dearchiver::create(context);
  ASSERT_FALSE(lacking);
  EXPECT_EQ(lacking.error().code, ErrorCode::not_found);
  EXPECT_NE(lacking.error().message.find("vkCreateGraphicsPipelines"), std::string::npos)
      << lacking.error().message;
  app_dispatch::withheld = nullptr;

  DeviceContext no_instance = vk_->device_context();
  no_instance.instance = VK_NULL_HANDLE;
  auto refused = Dearchiver::create(no_instance);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().code, ErrorCode::invalid_argument);
  EXPECT_NE(refused.error().message.find("DeviceContext::instance"), std::string::npos)
      << refused.error().message;
}

// The driver's own failure reaches the caller as a value, not only as text: an allocator that refuses
// every allocation makes lavapipe's create calls return VK_ERROR_OUT_OF_HOST_MEMORY.
TEST_F(Unpack, AFailedVulkanCallCarriesItsVkResult) {
  VkAllocationCallbacks refusing{};
  refusing.pfnAllocation = [](void*, size_t, size_t, VkSystemAllocationScope) -> void* { return nullptr; };
  refusing.pfnReallocation = [](void*, void*, size_t, size_t, VkSystemAllocationScope) -> void* {
    return nullptr;
  };
  refusing.pfnFree = [](void*, void*) {};
  DeviceContext context{vk_->physical_device, vk_->device};
  context.allocator = &refusing;
  auto dearchiver = Dearchiver::create(context);
  ASSERT_TRUE(dearchiver);
  ASSERT_TRUE(dearchiver->add_archive(Archive::from_file(STATEPACK_TEST_ARCHIVE).value()));
  for (const char* name : {"Fill Buffer PSO", "Gradient PSO"}) {
    auto pso = std::string(name) == "Gradient PSO" ? dearchiver->unpack_graphics(name)
                                                   : dearchiver->unpack_compute(name);
    ASSERT_FALSE(pso) << name;
    EXPECT_EQ(pso.error().code, ErrorCode::vulkan_error) << pso.error().message;
    EXPECT_EQ(pso.error().vk_result, VK_ERROR_OUT_OF_HOST_MEMORY) << pso.error().message;
    EXPECT_NE(pso.error().message.find("ErrorOutOfHostMemory"), std::string::npos) << pso.error().message;
  }
  // Every other error carries VK_SUCCESS.
  auto unknown = dearchiver->unpack_compute("No Such PSO");
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().code, ErrorCode::not_found);
  EXPECT_EQ(unknown.error().vk_result, VK_SUCCESS);
}

}  // namespace
}  // namespace statepack::testing
