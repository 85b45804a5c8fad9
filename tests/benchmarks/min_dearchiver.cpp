// Smallest real program that loads an archive and creates a compute pipeline with the dearchiver.
// Compared in size with min_glslang.cpp by tests/benchmarks/load_benchmark.sh.
#include <cstdio>

#include "statepack/bootstrap/host_tools.hpp"  // printable(): the name and the message may hold terminal escapes
#include "statepack/bootstrap/vulkan_context.hpp"
#include "statepack/dearchiver.hpp"

int main(int argc, char** argv) {
  if (argc != 3) return std::fprintf(stderr, "usage: min_dearchiver <archive> <compute pipeline>\n"), 2;
  auto vk = statepack::bootstrap::VulkanContext::create({false, false, {}});
  auto archive = statepack::Archive::from_file(argv[1]);
  if (!vk || !archive) return 1;
  auto dearchiver = statepack::Dearchiver::create((*vk)->device_context());
  if (!dearchiver || !dearchiver->add_archive(std::move(*archive))) return 1;
  auto pso = dearchiver->unpack_compute(argv[2]);
  if (!pso)
    return std::fprintf(stderr, "%s\n", statepack::bootstrap::printable(pso.error().message).c_str()), 1;
  std::printf("created '%s'\n", statepack::bootstrap::printable(argv[2]).c_str());
  return 0;
}
