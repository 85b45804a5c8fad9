// The consumer project's application, built against an installed statepack (find_package or
// pkg-config): it loads the archive its build packed and creates the pipeline on the first Vulkan
// device, so the installed headers, library and its dependencies are proven to link and work together.
// Built twice: consumer_app links the Vulkan loader and calls Vulkan by symbol; consumer_volk_app
// (STATEPACK_CONSUMER_VOLK) owns its dispatch through volk, links no libvulkan, and hands volk's
// vkGetInstanceProcAddr to the Dearchiver, as an engine with its own function table does.
// Usage: consumer_app <archive.spk>
#ifdef STATEPACK_CONSUMER_VOLK
#define VOLK_IMPLEMENTATION
#include <volk.h>  // before any Vulkan header: it declares the functions as pointers
#endif
#include <statepack/dearchiver.hpp>

#include <cstdio>
#include <vector>

namespace {

int fail(const char* what, const std::string& why) {
  std::fprintf(stderr, "consumer_app: %s: %s\n", what, why.c_str());
  return 1;
}

// The first device with a compute queue (lavapipe on a machine without a GPU).
bool pick_device(VkInstance instance, VkPhysicalDevice& physical_device, uint32_t& queue_family) {
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());
  for (VkPhysicalDevice candidate : devices) {
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(candidate, &families, nullptr);
    std::vector<VkQueueFamilyProperties> properties(families);
    vkGetPhysicalDeviceQueueFamilyProperties(candidate, &families, properties.data());
    for (uint32_t i = 0; i < families; ++i) {
      if (properties[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
        physical_device = candidate;
        queue_family = i;
        return true;
      }
    }
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return fail("usage", "consumer_app <archive.spk>");
  auto archive = statepack::Archive::from_file(argv[1]);
  if (!archive) return fail(argv[1], archive.error().message);
#ifdef STATEPACK_CONSUMER_VOLK
  if (volkInitialize() != VK_SUCCESS) return fail("volkInitialize", "no Vulkan loader");
#endif

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo instance_info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  instance_info.pApplicationInfo = &app;
  VkInstance instance = VK_NULL_HANDLE;
  if (vkCreateInstance(&instance_info, nullptr, &instance) != VK_SUCCESS)
    return fail("vkCreateInstance", "failed");
#ifdef STATEPACK_CONSUMER_VOLK
  volkLoadInstance(instance);
#endif
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  uint32_t queue_family = 0;
  if (!pick_device(instance, physical_device, queue_family))
    return fail("Vulkan", "no device with a compute queue");
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = queue_family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  VkDevice device = VK_NULL_HANDLE;
  if (vkCreateDevice(physical_device, &device_info, nullptr, &device) != VK_SUCCESS)
    return fail("vkCreateDevice", "failed");

  int status = 0;
  {  // the Dearchiver destroys its objects before the device goes
    statepack::DeviceContext context{physical_device, device};
    context.api_version = app.apiVersion;       // Vulkan 1.1: no 1.2 structure may reach the driver
    context.dynamic_rendering_enabled = false;  // not enabled above; compute does not need it
#ifdef STATEPACK_CONSUMER_VOLK
    context.instance = instance;  // the application's dispatch, not the system loader's
    context.get_instance_proc_addr = vkGetInstanceProcAddr;
#endif
    auto dearchiver = statepack::Dearchiver::create(context);
    if (!dearchiver) return fail("Dearchiver::create", dearchiver.error().message);
    if (auto added = dearchiver->add_archive(std::move(*archive)); !added)
      return fail("add_archive", added.error().message);
    auto pso = dearchiver->unpack_compute("Consumer PSO");
    if (!pso) {
      status = fail("unpack_compute", pso.error().message);
    } else {
      std::printf("consumer_app: unpacked '%s' (%zu set layout(s))%s\n", (*pso)->name.c_str(),
                  (*pso)->set_layouts.size(), context.get_instance_proc_addr ? " through volk" : "");
    }
  }
  vkDestroyDevice(device, nullptr);
  vkDestroyInstance(instance, nullptr);
  return status;
}
