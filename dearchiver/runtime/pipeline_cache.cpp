// VkPipelineCache data saved behind statepack's own header, checked against the device before the
// driver ever sees it: drivers trust their cache header and some misbehave on stale or damaged data.
//
// | off | type   | field                                                      |
// |-----|--------|------------------------------------------------------------|
// |   0 | u8[8]  | magic "SPKCACHE"                                           |
// |   8 | u32    | version (1)                                                |
// |  12 | u32    | header size (96)                                           |
// |  16 | u32    | vendorID                                                   |
// |  20 | u32    | deviceID                                                   |
// |  24 | u32    | driverVersion                                              |
// |  28 | u32    | driverID (VkDriverId; 0 before Vulkan 1.2)                 |
// |  32 | u8[16] | pipelineCacheUUID                                          |
// |  48 | u8[16] | deviceUUID (0 before Vulkan 1.1)                           |
// |  64 | u64    | XXH3-64 of driverName + "\n" + driverInfo                  |
// |  72 | u32    | pointer size of the process that saved it                  |
// |  76 | u32    | reserved, 0                                                |
// |  80 | u64    | data size                                                  |
// |  88 | u64    | XXH3-64 of the data                                        |
// |  96 | bytes  | the driver's vkGetPipelineCacheData output                 |
#include <xxhash.h>

#include <cstring>

#include "api_guard.hpp"

#include "statepack/dearchiver.hpp"
#include "support/failure.hpp"
#include "support/file_io.hpp"
#include "vk_result_string.hpp"
#include "vulkan_functions.hpp"

namespace statepack {
using namespace detail;  // the runtime's internals: this file defines the public API on top of them
namespace {

constexpr uint8_t kMagic[8] = {'S', 'P', 'K', 'C', 'A', 'C', 'H', 'E'};
constexpr uint32_t kVersion = 1, kHeaderSize = 96;

struct Identity {
  uint32_t vendor = 0, device = 0, driver_version = 0, driver_id = 0;
  uint8_t cache_uuid[16] = {}, device_uuid[16] = {};
  uint64_t driver_info_hash = 0;
  std::string driver_text;
};

Identity identity_of(const VulkanFunctions& vk, const DeviceContext& context) {
  Identity id;
  VkPhysicalDeviceProperties props;
  const VkPhysicalDevice physical_device = context.physical_device;
  vk.vkGetPhysicalDeviceProperties(physical_device, &props);
  props.apiVersion = effective_api_version(context, props.apiVersion);
  id.vendor = props.vendorID;
  id.device = props.deviceID;
  id.driver_version = props.driverVersion;
  std::memcpy(id.cache_uuid, props.pipelineCacheUUID, 16);
  if (props.apiVersion >= VK_API_VERSION_1_2 && vk.vkGetPhysicalDeviceProperties2) {
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceIDProperties ids{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES, &driver};
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &ids};
    vk.vkGetPhysicalDeviceProperties2(physical_device, &props2);
    id.driver_id = driver.driverID;
    std::memcpy(id.device_uuid, ids.deviceUUID, 16);
    id.driver_text = std::string(driver.driverName) + "\n" + driver.driverInfo;
  }
  id.driver_info_hash = XXH3_64bits(id.driver_text.data(), id.driver_text.size());
  return id;
}

void put32(std::vector<uint8_t>& out, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) out[at + i] = uint8_t(v >> (8 * i));
}
void put64(std::vector<uint8_t>& out, size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) out[at + i] = uint8_t(v >> (8 * i));
}
uint32_t get32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
uint64_t get64(const uint8_t* p) {
  return uint64_t(get32(p)) | uint64_t(get32(p + 4)) << 32;
}

std::string hex(uint32_t v) {
  char text[11];
  std::snprintf(text, sizeof text, "0x%x", v);
  return text;
}

// Empty when `file` may be handed to the driver, else why not.
std::string mismatch(std::span<const uint8_t> file, const Identity& id) {
  if (file.size() < kHeaderSize || std::memcmp(file.data(), kMagic, 8) != 0)
    return "not a statepack pipeline cache file";
  const uint8_t* h = file.data();
  if (get32(h + 8) != kVersion || get32(h + 12) != kHeaderSize)
    return "pipeline cache file of another version";
  if (get64(h + 80) != file.size() - kHeaderSize) return "truncated or padded pipeline cache file";
  if (get64(h + 88) != XXH3_64bits(h + kHeaderSize, file.size() - kHeaderSize))
    return "damaged pipeline cache file (data hash mismatch)";
  if (get32(h + 16) != id.vendor || get32(h + 20) != id.device)
    return "saved on another device (vendor " + hex(get32(h + 16)) + ", device " + hex(get32(h + 20)) +
           "; this is vendor " + hex(id.vendor) + ", device " + hex(id.device) + ")";
  if (get32(h + 28) != id.driver_id)
    return "saved with another driver (driver ID " + std::to_string(get32(h + 28)) + ")";
  if (get32(h + 24) != id.driver_version)
    return "saved with driver version " + hex(get32(h + 24)) + "; this driver is " + hex(id.driver_version);
  if (std::memcmp(h + 32, id.cache_uuid, 16) != 0) return "the driver's pipeline cache UUID differs";
  if (std::memcmp(h + 48, id.device_uuid, 16) != 0) return "the device UUID differs";
  if (get64(h + 64) != id.driver_info_hash) return "saved with another driver build (driver info differs)";
  if (get32(h + 72) != sizeof(void*))
    return "saved by a " + std::to_string(get32(h + 72) * 8) + "-bit process";
  return "";
}

}  // namespace

Result<PipelineCacheLoad> load_pipeline_cache(const DeviceContext& context,
                                              const std::filesystem::path& path) {
  return api_guard("load_pipeline_cache", [&]() -> Result<PipelineCacheLoad> {
    auto vk = load_vulkan_functions(context, "load_pipeline_cache");
    if (!vk) return vk.error();
    PipelineCacheLoad out;
    // Caches are driver blobs of a few megabytes; a larger file is not ours.
    auto read = read_regular_file(path, uint64_t{1} << 30);
    std::span<const uint8_t> file;
    if (read) {
      file = read->bytes();
      out.reason = mismatch(file, identity_of(*vk, context));
    } else if (std::error_code ec; !std::filesystem::exists(path, ec)) {
      out.reason = "no pipeline cache file at '" + path.string() + "'";
    } else {
      out.reason = read.error().message;
    }
    out.reused = out.reason.empty();
    VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
    if (out.reused) {
      info.initialDataSize = file.size() - kHeaderSize;
      info.pInitialData = file.data() + kHeaderSize;
    }
    if (VkResult r = vk->vkCreatePipelineCache(context.device, &info, context.allocator, &out.cache);
        r != VK_SUCCESS)
      return detail::failure(ErrorCode::vulkan_error, "vkCreatePipelineCache failed: " + vk_result_string(r),
                             r);
    return out;
  });
}

Result<void> save_pipeline_cache(const DeviceContext& context, VkPipelineCache cache,
                                 const std::filesystem::path& path) {
  return api_guard("save_pipeline_cache", [&]() -> Result<void> {
    auto vk = load_vulkan_functions(context, "save_pipeline_cache");
    if (!vk) return vk.error();
    size_t size = 0;
    if (VkResult r = vk->vkGetPipelineCacheData(context.device, cache, &size, nullptr); r != VK_SUCCESS)
      return detail::failure(ErrorCode::vulkan_error, "vkGetPipelineCacheData failed: " + vk_result_string(r),
                             r);
    std::vector<uint8_t> file(kHeaderSize + size);
    if (VkResult r = vk->vkGetPipelineCacheData(context.device, cache, &size, file.data() + kHeaderSize);
        r != VK_SUCCESS)
      return detail::failure(ErrorCode::vulkan_error, "vkGetPipelineCacheData failed: " + vk_result_string(r),
                             r);
    file.resize(kHeaderSize + size);
    const Identity id = identity_of(*vk, context);
    std::memcpy(file.data(), kMagic, 8);
    put32(file, 8, kVersion);
    put32(file, 12, kHeaderSize);
    put32(file, 16, id.vendor);
    put32(file, 20, id.device);
    put32(file, 24, id.driver_version);
    put32(file, 28, id.driver_id);
    std::memcpy(file.data() + 32, id.cache_uuid, 16);
    std::memcpy(file.data() + 48, id.device_uuid, 16);
    put64(file, 64, id.driver_info_hash);
    put32(file, 72, sizeof(void*));
    put32(file, 76, 0);
    put64(file, 80, size);
    put64(file, 88, XXH3_64bits(file.data() + kHeaderSize, size));
    return save_file_atomically(path, file);
  });
}

}  // namespace statepack
