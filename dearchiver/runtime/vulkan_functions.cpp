#include "vulkan_functions.hpp"

#include "support/failure.hpp"

#include <dlfcn.h>

#include <string>

namespace statepack::detail {
namespace {

// The system loader, opened once for the process and never closed (the functions outlive any caller).
// Its exported trampolines dispatch on the handle they are given, so no VkInstance is needed.
void* system_loader() {
  static void* const handle = [] {
    void* h = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
    return h ? h : dlopen("libvulkan.so", RTLD_NOW | RTLD_LOCAL);
  }();
  return handle;
}

Error missing(const char* caller, const char* name, const char* from) {
  return detail::failure(ErrorCode::not_found, std::string(caller) + ": " + from + " has no " + name +
                                                   "; the runtime needs it (Vulkan 1.0 core)");
}

}  // namespace

Result<VulkanFunctions> load_vulkan_functions(const DeviceContext& context, const char* caller) {
  VulkanFunctions f;
  const char* from = "the application's vkGetInstanceProcAddr";
  void* loader = nullptr;
  if (context.get_instance_proc_addr) {
    if (context.instance == VK_NULL_HANDLE)
      return detail::failure(ErrorCode::invalid_argument,
                             std::string(caller) +
                                 ": DeviceContext::get_instance_proc_addr needs DeviceContext::instance "
                                 "(the VkInstance the physical device belongs to)");
  } else {
    loader = system_loader();
    if (!loader)
      return detail::failure(
          ErrorCode::not_found,
          std::string(caller) +
              ": no Vulkan loader (libvulkan.so.1) could be opened; install it "
              "(Debian: libvulkan1) or pass your own dispatch in DeviceContext::get_instance_proc_addr");
    from = "the system Vulkan loader (libvulkan.so.1)";
  }
  // Instance-level functions through the application's dispatch, or the loader's exported symbols.
  auto instance_function = [&](const char* name) {
    return loader ? reinterpret_cast<PFN_vkVoidFunction>(dlsym(loader, name))
                  : context.get_instance_proc_addr(context.instance, name);
  };
#define STATEPACK_VK_LOAD(name) f.name = reinterpret_cast<PFN_##name>(instance_function(#name));
  STATEPACK_VK_INSTANCE_FUNCTIONS(STATEPACK_VK_LOAD)
  STATEPACK_VK_LOAD(vkGetPhysicalDeviceProperties2)
  STATEPACK_VK_LOAD(vkGetPhysicalDeviceFeatures2)
#undef STATEPACK_VK_LOAD
  if (context.get_device_proc_addr) f.vkGetDeviceProcAddr = context.get_device_proc_addr;
#define STATEPACK_VK_CHECK(name) \
  if (!f.name) return missing(caller, #name, from);
  STATEPACK_VK_INSTANCE_FUNCTIONS(STATEPACK_VK_CHECK)
#undef STATEPACK_VK_CHECK
  // Device-level functions straight from the driver: no loader trampoline on the hot path.
  const auto gdpa = f.vkGetDeviceProcAddr;
#define STATEPACK_VK_LOAD(name)                                       \
  f.name = reinterpret_cast<PFN_##name>(gdpa(context.device, #name)); \
  if (!f.name) return missing(caller, #name, "vkGetDeviceProcAddr for the given VkDevice");
  STATEPACK_VK_DEVICE_FUNCTIONS(STATEPACK_VK_LOAD)
#undef STATEPACK_VK_LOAD
  return f;
}

}  // namespace statepack::detail
