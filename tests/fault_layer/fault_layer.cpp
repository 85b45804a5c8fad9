// VK_LAYER_STATEPACK_test_faults: a Vulkan layer for tests that makes the driver fail the way real
// drivers do, so that `statepack verify` can be shown to survive it. A compute pipeline whose entry
// point is named CrashTheDriver kills the process inside vkCreateComputePipelines (SIGSEGV, as a
// driver's null dereference would); one named HangTheDriver never returns. Every other call goes to
// the next layer or the driver unchanged. An implicit layer, on when STATEPACK_TEST_FAULTS=1
// (fault_layer.json.in).
#include <vulkan/vk_layer.h>
#include <vulkan/vulkan.h>

#include <unistd.h>
#include <csignal>
#include <cstring>

namespace {

// One instance and one device per process is all the tests create.
PFN_vkGetInstanceProcAddr g_next_instance_proc = nullptr;
PFN_vkGetDeviceProcAddr g_next_device_proc = nullptr;
PFN_vkCreateComputePipelines g_next_create_compute = nullptr;
VkInstance g_instance = VK_NULL_HANDLE;

template <typename Info, VkStructureType kType>
Info* link_info(const void* next) {
  for (auto* s = static_cast<const VkBaseInStructure*>(next); s; s = s->pNext)
    if (s->sType == kType && reinterpret_cast<const Info*>(s)->function == VK_LAYER_LINK_INFO)
      return const_cast<Info*>(reinterpret_cast<const Info*>(s));
  return nullptr;
}

VKAPI_ATTR VkResult VKAPI_CALL create_instance(const VkInstanceCreateInfo* info,
                                               const VkAllocationCallbacks* alloc, VkInstance* instance) {
  auto* link =
      link_info<VkLayerInstanceCreateInfo, VK_STRUCTURE_TYPE_LOADER_INSTANCE_CREATE_INFO>(info->pNext);
  if (!link) return VK_ERROR_INITIALIZATION_FAILED;
  g_next_instance_proc = link->u.pLayerInfo->pfnNextGetInstanceProcAddr;
  link->u.pLayerInfo = link->u.pLayerInfo->pNext;
  auto next =
      reinterpret_cast<PFN_vkCreateInstance>(g_next_instance_proc(VK_NULL_HANDLE, "vkCreateInstance"));
  VkResult result = next(info, alloc, instance);
  if (result == VK_SUCCESS) g_instance = *instance;
  return result;
}

VKAPI_ATTR VkResult VKAPI_CALL create_device(VkPhysicalDevice gpu, const VkDeviceCreateInfo* info,
                                             const VkAllocationCallbacks* alloc, VkDevice* device) {
  auto* link = link_info<VkLayerDeviceCreateInfo, VK_STRUCTURE_TYPE_LOADER_DEVICE_CREATE_INFO>(info->pNext);
  if (!link) return VK_ERROR_INITIALIZATION_FAILED;
  PFN_vkGetInstanceProcAddr next_instance = link->u.pLayerInfo->pfnNextGetInstanceProcAddr;
  g_next_device_proc = link->u.pLayerInfo->pfnNextGetDeviceProcAddr;
  link->u.pLayerInfo = link->u.pLayerInfo->pNext;
  auto next = reinterpret_cast<PFN_vkCreateDevice>(next_instance(g_instance, "vkCreateDevice"));
  VkResult result = next(gpu, info, alloc, device);
  if (result == VK_SUCCESS)
    g_next_create_compute = reinterpret_cast<PFN_vkCreateComputePipelines>(
        g_next_device_proc(*device, "vkCreateComputePipelines"));
  return result;
}

VKAPI_ATTR VkResult VKAPI_CALL create_compute_pipelines(VkDevice device, VkPipelineCache cache,
                                                        uint32_t count,
                                                        const VkComputePipelineCreateInfo* infos,
                                                        const VkAllocationCallbacks* alloc,
                                                        VkPipeline* pipelines) {
  for (uint32_t i = 0; i < count; ++i) {
    const char* entry = infos[i].stage.pName;
    if (entry && std::strcmp(entry, "CrashTheDriver") == 0) std::raise(SIGSEGV);
    if (entry && std::strcmp(entry, "HangTheDriver") == 0)
      for (;;) pause();
  }
  return g_next_create_compute(device, cache, count, infos, alloc, pipelines);
}

}  // namespace

extern "C" {

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL vkGetDeviceProcAddr(VkDevice device, const char* name) {
  if (std::strcmp(name, "vkCreateComputePipelines") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&create_compute_pipelines);
  if (std::strcmp(name, "vkGetDeviceProcAddr") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&vkGetDeviceProcAddr);
  return g_next_device_proc ? g_next_device_proc(device, name) : nullptr;
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL vkGetInstanceProcAddr(VkInstance instance, const char* name) {
  if (std::strcmp(name, "vkCreateInstance") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&create_instance);
  if (std::strcmp(name, "vkCreateDevice") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&create_device);
  if (std::strcmp(name, "vkGetInstanceProcAddr") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&vkGetInstanceProcAddr);
  if (std::strcmp(name, "vkGetDeviceProcAddr") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&vkGetDeviceProcAddr);
  if (std::strcmp(name, "vkCreateComputePipelines") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&create_compute_pipelines);
  return g_next_instance_proc ? g_next_instance_proc(instance, name) : nullptr;
}

}  // extern "C"
