// Load benchmark: archive bytes -> ready VkPipelines, against
//   (b) the driver's own limit: the same pipelines created with bare Vulkan calls from SPIR-V already
//       in memory (layouts and states known, nothing parsed or checked), and
//   (a) compiling the same GLSL/HLSL at run time with glslang, then creating the pipelines as in (b).
// Prints a Markdown table: minima, medians and the spread of the per-run overhead. Run through
// tests/benchmarks/load_benchmark.sh.
// Usage: load_benchmark <archive.spk> <notation.json> <shader dir> [repeats]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

// Client requests: a few no-op instructions unless run under callgrind. Without valgrind's headers (it is
// in .ci/setup) the counted mode counts the whole program, and load_benchmark.sh skips the count.
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_TOGGLE_COLLECT
#endif

#include "arguments.hpp"
#include "format/archive_format.hpp"
#include "notation/notation.hpp"
#include "shaders/shader_compiler.hpp"
#include "statepack/bootstrap/host_tools.hpp"
#include "statepack/bootstrap/vulkan_context.hpp"
#include "statepack/dearchiver.hpp"
#include "support/file_io.hpp"

namespace {

using namespace statepack;
using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double time_ms(const std::function<void()>& work) {
  auto start = Clock::now();
  work();
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// (b): the minimum a loader must do, with every input already decoded: modules, set layouts,
// pipeline layouts and pipelines, each shared object once, with plain Vulkan calls.
class BareCreator {
 public:
  BareCreator(VkDevice device, const format::Contents& c) : device_(device), c_(c) {}
  ~BareCreator() {
    for (auto p : pipelines_) vkDestroyPipeline(device_, p, nullptr);
    for (auto l : pipeline_layouts_) vkDestroyPipelineLayout(device_, l, nullptr);
    for (auto l : set_layouts_) vkDestroyDescriptorSetLayout(device_, l, nullptr);
    for (auto m : modules_) vkDestroyShaderModule(device_, m, nullptr);
  }

  // `spirv` per blob index: the archive's own, or freshly compiled ones for (a).
  // Milliseconds of the last create_all spent before its first pipeline (modules and layouts), and in
  // vkCreate*Pipelines calls, timed as the Dearchiver times them (PipelineCreation::time).
  double objects_ms = 0;
  double pipelines_ms = 0;
  void create_all(const std::vector<std::vector<uint32_t>>& spirv) {
    const auto start = Clock::now();
    pipelines_ms = 0;
    bool first_pipeline = true;
    for (const auto& words : spirv) {
      VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
      info.codeSize = words.size() * 4;
      info.pCode = words.data();
      vkCreateShaderModule(device_, &info, nullptr, &modules_.emplace_back());
    }
    VkDescriptorSetLayoutCreateInfo empty{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    vkCreateDescriptorSetLayout(device_, &empty, nullptr, &empty_layout_);
    set_layouts_.push_back(empty_layout_);
    std::vector<VkDescriptorSetLayout> by_index;
    for (const auto& l : c_.set_layouts) {
      std::vector<VkDescriptorSetLayoutBinding> bindings;
      for (const auto& b : l.bindings)
        bindings.push_back({b.binding, VkDescriptorType(b.descriptor_type), b.count, b.stage_flags, nullptr});
      VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
      info.bindingCount = static_cast<uint32_t>(bindings.size());
      info.pBindings = bindings.data();
      vkCreateDescriptorSetLayout(device_, &info, nullptr, &by_index.emplace_back());
      set_layouts_.push_back(by_index.back());
    }
    std::map<std::tuple<std::vector<VkDescriptorSetLayout>, uint32_t, uint32_t>, VkPipelineLayout> layouts;
    for (const auto& p : c_.pipelines) {
      std::vector<VkDescriptorSetLayout> sets;
      for (uint32_t l : p.set_layouts) sets.push_back(l == format::kNone ? empty_layout_ : by_index[l]);
      auto key = std::tuple{sets, p.push_constant_size, p.push_constant_stages};
      auto it = layouts.find(key);
      if (it == layouts.end()) {
        VkPushConstantRange range{p.push_constant_stages, 0, p.push_constant_size};
        VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        info.setLayoutCount = static_cast<uint32_t>(sets.size());
        info.pSetLayouts = sets.data();
        info.pushConstantRangeCount = p.push_constant_size ? 1 : 0;
        info.pPushConstantRanges = &range;
        VkPipelineLayout layout;
        vkCreatePipelineLayout(device_, &info, nullptr, &layout);
        pipeline_layouts_.push_back(layout);
        it = layouts.emplace(key, layout).first;
      }
      if (first_pipeline)
        objects_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      first_pipeline = false;
      create_pipeline(p, it->second);
    }
  }

 private:
  void create_pipeline(const format::Pipeline& p, VkPipelineLayout layout) {
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    for (uint32_t s : p.shaders) {
      VkPipelineShaderStageCreateInfo stage{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
      stage.stage = VkShaderStageFlagBits(c_.shaders[s].stage);
      stage.module = modules_[c_.shaders[s].blob];
      stage.pName = c_.shaders[s].entry_point.c_str();
      stages.push_back(stage);
    }
    VkPipeline pipeline = VK_NULL_HANDLE;
    if (p.kind == format::PipelineKind::compute) {
      VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
      info.stage = stages[0];
      info.layout = layout;
      const auto call = Clock::now();
      vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
      pipelines_ms += std::chrono::duration<double, std::milli>(Clock::now() - call).count();
    } else {
      const format::GraphicsState& g = p.graphics;
      VkPipelineVertexInputStateCreateInfo vertex{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
      VkPipelineInputAssemblyStateCreateInfo assembly{
          VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
      assembly.topology = VkPrimitiveTopology(g.topology);
      VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
      viewport.viewportCount = viewport.scissorCount = 1;
      VkPipelineRasterizationStateCreateInfo raster{
          VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
      raster.cullMode = g.cull_mode;
      raster.frontFace = VkFrontFace(g.front_face);
      raster.lineWidth = 1;
      VkPipelineMultisampleStateCreateInfo multisample{
          VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
      multisample.rasterizationSamples = VkSampleCountFlagBits(g.samples);
      VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
      std::vector<VkPipelineColorBlendAttachmentState> attachments(g.color_count);
      for (auto& a : attachments) a.colorWriteMask = 0xF;
      VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
      blend.attachmentCount = g.color_count;
      blend.pAttachments = attachments.data();
      VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
      VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
      dynamic.dynamicStateCount = 2;
      dynamic.pDynamicStates = dynamic_states;
      std::vector<VkFormat> formats;
      for (uint32_t i = 0; i < g.color_count; ++i) formats.push_back(VkFormat(g.color_formats[i]));
      VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
      rendering.colorAttachmentCount = g.color_count;
      rendering.pColorAttachmentFormats = formats.data();
      VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
      info.pNext = &rendering;
      info.stageCount = static_cast<uint32_t>(stages.size());
      info.pStages = stages.data();
      info.pVertexInputState = &vertex;
      info.pInputAssemblyState = &assembly;
      info.pViewportState = &viewport;
      info.pRasterizationState = &raster;
      info.pMultisampleState = &multisample;
      info.pDepthStencilState = &depth;
      info.pColorBlendState = &blend;
      info.pDynamicState = &dynamic;
      info.layout = layout;
      const auto call = Clock::now();
      vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
      pipelines_ms += std::chrono::duration<double, std::milli>(Clock::now() - call).count();
    }
    pipelines_.push_back(pipeline);
  }

  VkDevice device_;
  const format::Contents& c_;
  VkDescriptorSetLayout empty_layout_ = VK_NULL_HANDLE;
  std::vector<VkShaderModule> modules_;
  std::vector<VkDescriptorSetLayout> set_layouts_;
  std::vector<VkPipelineLayout> pipeline_layouts_;
  std::vector<VkPipeline> pipelines_;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: load_benchmark <archive.spk> <notation.json> <shader dir> [repeats]\n");
    return 2;
  }
  const std::string archive_path = argv[1];
  const auto repeats_given = argc > 4 ? statepack::benchmarks::positive_count(argv[4]) : 5;
  if (argc > 5)
    return std::fprintf(stderr, "load_benchmark: unexpected argument '%s'\n",
                        statepack::bootstrap::printable(argv[5]).c_str()),
           2;
  if (!repeats_given)
    return std::fprintf(stderr, "load_benchmark: repeats must be a number from 1, not '%s'\n",
                        statepack::bootstrap::printable(argv[4]).c_str()),
           2;
  const int repeats = *repeats_given;
  auto file = detail::read_regular_file(archive_path, uint64_t{0xFFFFFFFFu});
  if (!file)
    return std::fprintf(stderr, "%s\n", statepack::bootstrap::printable(file.error().message).c_str()), 1;
  std::span<const uint8_t> bytes = file->bytes();

  bootstrap::VulkanContextOptions options;
  options.validation = false;  // timing the driver, not the layer
  auto vk = bootstrap::VulkanContext::create(options);
  if (!vk)
    return std::fprintf(stderr, "Vulkan: %s\n", statepack::bootstrap::printable(vk.error().message).c_str()),
           1;
  VkDevice device = (*vk)->device;

  auto decoded = format::decode(bytes);
  if (!decoded)
    return std::fprintf(stderr, "%s\n", statepack::bootstrap::printable(decoded.error().message).c_str()), 1;
  const format::Contents& contents = *decoded;
  std::vector<std::vector<uint32_t>> archived_spirv;
  for (auto blob : contents.spirv) archived_spirv.emplace_back(blob.begin(), blob.end());

  // (a) needs the sources: read the notation and compile each distinct shader with glslang.
  packager::Notation notation;
  packager::Diagnostics diag;
  packager::NotationOptions notation_options;
  notation_options.shader_dirs.emplace_back(argv[3]);
  packager::read_notation(argv[2], notation_options, notation, diag);
  packager::resolve_references(notation, diag);
  if (diag.has_errors()) return diag.print(std::cerr), 1;
  // Each distinct (name, stage) once, as an application compiling at run time would.
  std::vector<const packager::ShaderDesc*> sources;
  {
    std::map<std::string, const packager::ShaderDesc*> by_name;
    for (const auto& p : notation.pipelines)
      for (const auto& s : p.shaders) by_name.emplace(s.name + "/" + std::to_string(s.stage), &s);
    for (const auto& [key, s] : by_name) sources.push_back(s);
  }
  packager::CompileOptions compile_options;
  compile_options.include_dirs.emplace_back(argv[3]);

  const uint32_t cores = std::max(1u, std::thread::hardware_concurrency());
  std::vector<double> bare_objects;    // bare: modules, set layouts and the first pipeline layout
  std::vector<double> bare_pipelines;  // bare: its vkCreate*Pipelines calls
  auto bare_run = [&] {
    return time_ms([&] {
      BareCreator creator(device, contents);
      creator.create_all(archived_spirv);
      bare_objects.push_back(creator.objects_ms);
      bare_pipelines.push_back(creator.pipelines_ms);
    });
  };
  // Where statepack's time goes, per single-thread run: loading (decode, checksums, the SPIR-V walks and
  // checks), Dearchiver::create, unpack_all beside the driver's own pipeline creation (planning, state
  // checks, shader modules and layouts), and destruction.
  std::vector<double> t_load, t_create, t_unpack, t_driver, t_destroy;
  auto since = [](Clock::time_point from) {
    return std::chrono::duration<double, std::milli>(Clock::now() - from).count();
  };
  auto ours_run = [&](uint32_t threads) {
    return time_ms([&] {
      auto start = Clock::now();
      auto archive = Archive::from_memory(bytes);
      const double load = since(start);
      start = Clock::now();
      std::optional<Dearchiver> dearchiver = Dearchiver::create((*vk)->device_context()).value();
      (void)dearchiver->add_archive(std::move(*archive));
      const double create = since(start);
      start = Clock::now();
      UnpackAllOptions unpack_options;
      unpack_options.threads = threads;
      auto all = dearchiver->unpack_all(unpack_options);
      if (!all || !all->ok()) std::fprintf(stderr, "unpack_all failed\n"), std::exit(1);
      const double unpack = since(start);
      start = Clock::now();
      dearchiver.reset();
      if (threads != 1) return;
      t_load.push_back(load);
      t_create.push_back(create);
      t_unpack.push_back(unpack);
      t_driver.push_back(std::chrono::duration<double, std::milli>(all->creation_time).count());
      t_destroy.push_back(since(start));
    });
  };
  // The compared paths alternate run by run, and which goes first alternates too, so that a machine
  // whose load drifts (another process, a CPU's clock) weighs on both alike; each run's overhead is
  // taken against the bare run beside it.
  std::vector<double> bare, ours_one, ours_all, glslang_compile, paired;
  // For a profiler or an instruction count: one path only (STATEPACK_BENCH_ONLY=statepack or bare), once
  // to warm up and then `repeats` times, each run inside CALLGRIND_TOGGLE_COLLECT (run it under
  // `valgrind --tool=callgrind --collect-atstart=no`: what is counted is those runs and nothing else).
  if (const char* only = std::getenv("STATEPACK_BENCH_ONLY"); only && *only) {
    const bool bare_only = std::string_view(only) == "bare";
    if (!bare_only && std::string_view(only) != "statepack")
      return std::fprintf(stderr, "STATEPACK_BENCH_ONLY is 'statepack' or 'bare'\n"), 2;
    auto one = [&] { bare_only ? (void)bare_run() : (void)ours_run(1); };
    one();
    for (int r = 0; r < repeats; ++r) {
      CALLGRIND_TOGGLE_COLLECT;
      one();
      CALLGRIND_TOGGLE_COLLECT;
    }
    return 0;
  }
  for (int r = 0; r < repeats; ++r) {
    double b = 0, one = 0;
    if (r % 2 == 0) {
      b = bare_run();
      one = ours_run(1);
    } else {
      one = ours_run(1);
      b = bare_run();
    }
    bare.push_back(b);
    ours_one.push_back(one);
    paired.push_back(100.0 * (one - b) / b);
    ours_all.push_back(ours_run(cores));
    if (r < 5)  // glslang is far slower; five runs say enough
      glslang_compile.push_back(time_ms([&] {
        for (const auto* s : sources) {
          auto compiled = packager::compile_shader(*s, compile_options, diag);
          if (!compiled.ok) diag.print(std::cerr), std::exit(1);
        }
      }));
  }
  auto percentile = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
  };
  const double b_min = percentile(bare, 0), b_med = median(bare), one_min = percentile(ours_one, 0),
               one_med = median(ours_one), all = median(ours_all), compile = median(glslang_compile);
  std::printf(
      "| archive | pipelines | (b) bare Vulkan min / median (ms) | statepack, 1 thread min / median (ms) | "
      "overhead: of the minima, of the medians | per run: median [10th, 90th percentile] | "
      "statepack, %u threads (ms) | (a) glslang compile + create (ms) |\n",
      cores);
  std::printf("|---|---|---|---|---|---|---|---|\n");
  std::printf(
      "| %s | %zu | %.2f / %.2f | %.2f / %.2f | %+.1f %%, %+.1f %% | %+.1f %% [%+.1f, %+.1f] | %.1f | %.1f "
      "(compile %.1f) |\n",
      statepack::bootstrap::printable(std::filesystem::path(archive_path).filename().string()).c_str(),
      contents.pipelines.size(), b_min, b_med, one_min, one_med, 100.0 * (one_min - b_min) / b_min,
      100.0 * (one_med - b_med) / b_med, median(paired), percentile(paired, 0.1), percentile(paired, 0.9),
      all, compile + b_med, compile);
  if (std::getenv("STATEPACK_BENCH_BREAKDOWN"))
    std::printf(
        "\n| medians (ms) | Archive::from_memory | Dearchiver::create | unpack_all | of it, "
        "vkCreate*Pipelines | destruction | (b): modules and layouts before its first pipeline | (b): "
        "vkCreate*Pipelines |\n"
        "|---|---|---|---|---|---|---|---|\n| %s, 1 thread | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f "
        "|\n",
        statepack::bootstrap::printable(std::filesystem::path(archive_path).filename().string()).c_str(),
        median(t_load), median(t_create), median(t_unpack), median(t_driver), median(t_destroy),
        median(bare_objects), median(bare_pipelines));
  return 0;
}
