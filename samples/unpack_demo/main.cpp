// unpack_demo: loads a statepack archive, unpacks every pipeline on the Vulkan device (lavapipe on a
// machine without a GPU), prints what it created, and runs the compute pipeline once to show it works.
// With --watch it then stays, reloading the archive whenever a new build of it is written (statepack
// pack --watch), one line per reload. Links libstatepack_dearchiver only: no shader compiler.
#include <cinttypes>
#include <csignal>
#include <cstdio>
#include <string>
#include <thread>

#include <vulkan/vulkan.hpp>  // vk::to_string: Vulkan-Hpp names every enum

#include "statepack/bootstrap/host_tools.hpp"
#include "statepack/bootstrap/vulkan_context.hpp"
#include "statepack/dearchiver.hpp"

namespace {

// Names and paths come from the archive or the command line: escaped before they reach the terminal.
using statepack::bootstrap::printable;

int fail(const std::string& what, const statepack::Error& e) {
  std::fprintf(stderr, "unpack_demo: %s: %s (%s)\n", printable(what).c_str(), printable(e.message).c_str(),
               statepack::to_string(e.code));
  return 1;
}

// Fills a buffer with the compute pipeline and prints the first values.
int run_fill_buffer(statepack::bootstrap::VulkanContext& vk, const statepack::UnpackedPipeline& pso) {
  const statepack::BindingInfo* values = pso.find_binding("Values");
  if (!values) return std::fprintf(stderr, "unpack_demo: 'Values' binding missing\n"), 1;
  constexpr uint32_t kCount = 16;
  auto buffer = statepack::bootstrap::create_host_buffer(vk, kCount * sizeof(uint32_t),
                                                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  if (!buffer) return fail("buffer", buffer.error());
  auto set = statepack::bootstrap::bind_storage_buffer(vk, pso.set_layouts[values->set], values->binding,
                                                       (*buffer)->buffer);
  if (!set) return fail("descriptor set", set.error());
  const uint32_t params[3] = {kCount, 3, 1};
  auto done = vk.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pso.pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pso.layout, values->set, 1, &(*set)->set, 0,
                            nullptr);
    vkCmdPushConstants(cmd, pso.layout, pso.push_constant_stages, 0, sizeof params, params);
    vkCmdDispatch(cmd, 1, 1, 1);
  });
  if (!done) return fail("dispatch", done.error());
  std::printf("  ran '%s': values =", printable(pso.name).c_str());
  for (uint32_t i = 0; i < kCount; ++i)
    std::printf(" %u", static_cast<const uint32_t*>((*buffer)->mapped)[i]);
  std::printf("\n");
  return 0;
}

volatile std::sig_atomic_t stop_requested = 0;
void request_stop(int) {
  stop_requested = 1;
}

// Names joined for one line: 'A', 'B'.
std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "'" : ", '") + printable(n) + "'";
  return out;
}

// Polls the archive file until SIGINT or SIGTERM; one line per reload: what was re-created, kept,
// removed, added, and what failed (the old pipeline stays). The compute pipeline runs again after a
// reload that changed it.
int watch(statepack::bootstrap::VulkanContext& vk, statepack::Dearchiver& dearchiver,
          const std::string& path) {
  auto file = statepack::ArchiveFileWatch::create(path);
  if (!file) return fail("watch", file.error());
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  std::printf("watching %s (Ctrl-C ends)\n", printable(path).c_str());
  std::fflush(stdout);
  int status = 0;
  for (unsigned reloads = 0; !stop_requested;) {
    auto polled = file->poll();
    if (!polled) {
      std::printf("not reloaded: %s\n", printable(polled.error().message).c_str());
    } else if (*polled) {
      auto report = dearchiver.reload(std::move(**polled));
      if (!report) {
        std::printf("not reloaded: %s\n", printable(report.error().message).c_str());
      } else {
        std::printf("reload %u: re-created %zu [%s], kept %zu [%s]", ++reloads, report->recreated.size(),
                    quoted_list(report->recreated).c_str(), report->kept.size(),
                    quoted_list(report->kept).c_str());
        if (!report->removed.empty()) std::printf(", removed [%s]", quoted_list(report->removed).c_str());
        if (!report->added.empty()) std::printf(", added [%s]", quoted_list(report->added).c_str());
        std::printf("\n");
        for (const auto& f : report->failures)
          std::printf("  not re-created '%s': %s\n", printable(f.object.name).c_str(),
                      printable(f.error.message).c_str());
        for (const auto& name : report->recreated)
          if (name == "Fill Buffer PSO")
            if (auto pso = dearchiver.unpack_compute(name)) status |= run_fill_buffer(vk, **pso);
        dearchiver.destroy_retired();  // run_fill_buffer waited: the device is idle
      }
    }
    std::fflush(stdout);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  const bool watching = !args.empty() && args[0] == "--watch";
  if (watching) args.erase(args.begin());
  std::string path = args.empty() ? STATEPACK_DEFAULT_ARCHIVE : args[0];
  if (path == "-h" || path == "--help") {
    std::printf(
        "usage: unpack_demo [--watch] [archive.spk]\n  default: %s\n"
        "  --watch: stay, and reload the archive whenever a new build of it is written\n",
        STATEPACK_DEFAULT_ARCHIVE);
    return 0;
  }
  // One archive at most, and no options but --watch and --help: anything else is a usage error (exit 2),
  // not a file name or an argument silently dropped.
  if (args.size() > 1 || path.starts_with("-")) {
    std::fprintf(stderr,
                 "unpack_demo: error: unexpected argument '%s'\nusage: unpack_demo [--watch] [archive.spk]\n",
                 printable(args.size() > 1 ? args[1] : path).c_str());
    return 2;
  }
  auto archive = statepack::Archive::from_file(path);
  if (!archive) return fail("load", archive.error());
  const std::vector<statepack::ObjectInfo> objects = archive->objects();
  std::printf("archive %s: format v%u, content version %u, %zu named object(s)\n", printable(path).c_str(),
              archive->format_version(), archive->content_version(), objects.size());

  statepack::bootstrap::VulkanContextOptions options;
  options.validation = true;
  auto vk = statepack::bootstrap::VulkanContext::create(options);
  if (!vk) return fail("Vulkan", vk.error());
  std::printf("device: %s (%s), validation layer on\n", printable((*vk)->device_name).c_str(),
              printable((*vk)->driver_name).c_str());

  auto dearchiver = statepack::Dearchiver::create((*vk)->device_context());
  if (!dearchiver) return fail("dearchiver", dearchiver.error());
  if (auto added = dearchiver->add_archive(std::move(*archive)); !added)
    return fail("add archive", added.error());

  int status = 0;
  for (const auto& [name, kind] : objects) {
    if (kind != statepack::ObjectKind::compute_pipeline && kind != statepack::ObjectKind::graphics_pipeline)
      continue;
    bool compute = kind == statepack::ObjectKind::compute_pipeline;
    auto pso = compute ? dearchiver->unpack_compute(name) : dearchiver->unpack_graphics(name);
    if (!pso) return fail("unpack '" + name + "'", pso.error());
    const statepack::UnpackedPipeline& p = **pso;
    std::printf(
        "unpacked '%s' (%s): VkPipeline 0x%" PRIx64 ", VkPipelineLayout 0x%" PRIx64 ", %zu set layout(s)",
        printable(p.name).c_str(), compute ? "compute" : "graphics", reinterpret_cast<uint64_t>(p.pipeline),
        reinterpret_cast<uint64_t>(p.layout), p.set_layouts.size());
    if (p.push_constant_size) std::printf(", %u bytes of push constants", p.push_constant_size);
    std::printf("\n");
    for (const auto& b : p.bindings)
      std::printf("  set %u binding %u: '%s' (%s x%u)\n", b.set, b.binding, printable(b.name).c_str(),
                  vk::to_string(vk::DescriptorType(b.type)).c_str(), b.count);
    if (compute && name == "Fill Buffer PSO") status |= run_fill_buffer(**vk, p);
  }
  if (watching) status |= watch(**vk, *dearchiver, path);
  auto messages = (*vk)->validation_messages();
  for (const auto& m : messages) std::fprintf(stderr, "%s\n", printable(m).c_str());
  std::printf("%zu validation message(s)\n", messages.size());
  return status != 0 || !messages.empty() ? 1 : 0;
}
