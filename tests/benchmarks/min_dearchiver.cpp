// Smallest real program that loads an archive and creates a compute pipeline with the dearchiver.
// Compared in size with min_glslang.cpp by tests/benchmarks/load_benchmark.sh.
#include <cstdio>

#include "min_device.hpp"
#include "statepack/dearchiver.hpp"

int main(int argc, char** argv) {
  if (argc != 3) return std::fprintf(stderr, "usage: min_dearchiver <archive> <compute pipeline>\n"), 2;
  min_device::Device vk;
  auto archive = statepack::Archive::from_file(argv[1]);
  if (!min_device::create(vk) || !archive) return 1;
  statepack::DeviceContext context;
  context.physical_device = vk.physical_device;
  context.device = vk.device;
  context.dynamic_rendering_enabled = false;  // (a compute pipeline: no render pass either way)
  context.instance = vk.instance;
  context.get_instance_proc_addr = vkGetInstanceProcAddr;
  context.api_version = VK_API_VERSION_1_0;  // what min_device's instance asked for
  int result = 1;
  {
    auto dearchiver = statepack::Dearchiver::create(context);
    if (!dearchiver || !dearchiver->add_archive(std::move(*archive))) return 1;
    auto pso = dearchiver->unpack_compute(argv[2]);
    if (!pso) {
      std::fprintf(stderr, "%s\n", min_device::printable(pso.error().message).c_str());
    } else {
      std::printf("created '%s'\n", min_device::printable(argv[2]).c_str());
      result = 0;
    }
  }
  return result;
}
