// Re-sealed mutations: thousands of deterministic edits of real archives, each re-sealed so that the
// checksums pass, then loaded and unpacked on lavapipe with the validation layer on. Every outcome must
// be a Result (an error or objects), never a crash and never a validation message: what reaches Vulkan
// has been checked first. Structural edits change decoded fields (indices, counts, enums, limits);
// byte edits change the encoded records and tables; SPIR-V edits change declarations (and must then
// pass our checks against the records) or name ids nothing defines (and must be refused at load; the
// SPIR-V code is not otherwise validated: see docs/api.md).
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>

#include "common/forged_archive.hpp"
#include "common/vulkan_test_fixture.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

using Rng = std::mt19937;

uint32_t pick(Rng& rng, uint32_t below) {
  return below == 0 ? 0 : std::uniform_int_distribution<uint32_t>(0, below - 1)(rng);
}
// Interesting values for a u32: small, boundary, absurd.
uint32_t any_u32(Rng& rng) {
  static constexpr uint32_t kValues[] = {
      0,    1,    2,     3,        4,   7,    8,    9,      16,         64,         128,        256,
      2048, 4096, 65536, 1u << 20, 255, 1000, 2047, 0xFFFF, 0x7FFFFFFC, 0x7FFFFFFF, 0xFFFFFFFE, 0xFFFFFFFF};
  return pick(rng, 4) == 0 ? static_cast<uint32_t>(rng()) : kValues[pick(rng, std::size(kValues))];
}
uint32_t any_index(Rng& rng, size_t size) {
  return pick(rng, 5) == 0 ? format::kNone : pick(rng, static_cast<uint32_t>(size + 1));
}

// One structural edit of the pipeline `p` or of something it uses; returns what was done.
std::string mutate_structure(format::Contents& c, format::Pipeline& p, Rng& rng) {
  format::GraphicsState& g = p.graphics;
  switch (pick(rng, 20)) {
    case 0:
      if (!p.set_layouts.empty())
        p.set_layouts.erase(p.set_layouts.begin() + pick(rng, uint32_t(p.set_layouts.size())));
      return "drop a set";
    case 1:
      p.set_layouts.resize(pick(rng, 12), any_index(rng, c.set_layouts.size()));
      return "resize the sets";
    case 2:
      if (!p.set_layouts.empty())
        p.set_layouts[pick(rng, uint32_t(p.set_layouts.size()))] = any_index(rng, c.set_layouts.size());
      return "swap a set layout";
    case 3:
    case 4: {
      if (c.set_layouts.empty()) return "none";
      auto& layout = c.set_layouts[pick(rng, uint32_t(c.set_layouts.size()))];
      if (layout.bindings.empty()) return "none";
      auto& b = layout.bindings[pick(rng, uint32_t(layout.bindings.size()))];
      switch (pick(rng, 5)) {
        case 0:
          b.descriptor_type = pick(rng, 11);
          return "descriptor type " + std::to_string(b.descriptor_type);
        case 1:
          b.stage_flags = pick(rng, 64);
          return "binding stages " + std::to_string(b.stage_flags);
        case 2:
          b.count = any_u32(rng);
          return "descriptor count " + std::to_string(b.count);
        case 3:
          b.binding = any_u32(rng);
          return "binding number " + std::to_string(b.binding);
        default:
          b.immutable_sampler = any_index(rng, c.samplers.size());
          return "immutable sampler";
      }
    }
    case 5:
      p.push_constant_size = pick(rng, 2) ? any_u32(rng) & ~3u : 4 * pick(rng, 80);
      return "push constant size " + std::to_string(p.push_constant_size);
    case 6:
      p.push_constant_stages = pick(rng, 64);
      return "push constant stages " + std::to_string(p.push_constant_stages);
    case 7: {
      if (c.shaders.empty()) return "none";
      auto& s = c.shaders[pick(rng, uint32_t(c.shaders.size()))];
      switch (pick(rng, 3)) {
        case 0:
          s.stage = 1u << pick(rng, 6);
          return "shader stage";
        case 1:
          s.entry_point = pick(rng, 2) ? "main" : "ps_main";
          return "entry point " + s.entry_point;
        default:
          s.blob = pick(rng, uint32_t(c.spirv.size()));
          return "shader blob";
      }
    }
    case 8:
      if (!p.shaders.empty())
        p.shaders[pick(rng, uint32_t(p.shaders.size()))] = pick(rng, uint32_t(c.shaders.size()));
      return "pipeline shader";
    case 9:
      g.samples = 1u << pick(rng, 8);
      return "samples " + std::to_string(g.samples);
    case 10:
      g.color_count = pick(rng, 10);
      return "color count " + std::to_string(g.color_count);
    case 11:
      g.color_formats[pick(rng, 8)] = pick(rng, 185);
      return "color format";
    case 12:
      g.depth_stencil_format = pick(rng, 4) ? pick(rng, 185) : 126 + pick(rng, 5);
      return "depth format " + std::to_string(g.depth_stencil_format);
    case 13: {
      auto& b = g.blend[pick(rng, 8)];
      b.enable = pick(rng, 2);
      b.src_color = pick(rng, 19), b.dst_alpha = pick(rng, 19), b.color_op = pick(rng, 5);
      b.write_mask = pick(rng, 16);
      return "blend";
    }
    case 14: {
      if (g.vertex_bindings.empty() || pick(rng, 3) == 0) {
        g.vertex_bindings.push_back({any_u32(rng), any_u32(rng), pick(rng, 2)});
        return "add vertex binding";
      }
      auto& b = g.vertex_bindings[pick(rng, uint32_t(g.vertex_bindings.size()))];
      (pick(rng, 2) ? b.binding : b.stride) = any_u32(rng);
      return "vertex binding " + std::to_string(b.binding) + " stride " + std::to_string(b.stride);
    }
    case 15: {
      if (g.vertex_attributes.empty() || pick(rng, 4) == 0) {
        if (g.vertex_bindings.empty()) return "none";
        g.vertex_attributes.push_back(
            {any_u32(rng), g.vertex_bindings[0].binding, pick(rng, 185), any_u32(rng)});
        return "add vertex attribute";
      }
      auto& a = g.vertex_attributes[pick(rng, uint32_t(g.vertex_attributes.size()))];
      switch (pick(rng, 3)) {
        case 0:
          a.location = any_u32(rng);
          return "attribute location " + std::to_string(a.location);
        case 1:
          a.format = pick(rng, 185);
          return "attribute format " + std::to_string(a.format);
        default:
          a.offset = any_u32(rng);
          return "attribute offset " + std::to_string(a.offset);
      }
    }
    case 16:
      g.topology = pick(rng, 10), g.polygon_mode = pick(rng, 3), g.cull_mode = pick(rng, 4);
      g.depth_clamp = pick(rng, 2), g.depth_bias_clamp = float(pick(rng, 2));
      return "rasterizer";
    case 17: {
      if (c.render_passes.empty()) return "none";
      auto& rp = c.render_passes[pick(rng, uint32_t(c.render_passes.size()))];
      if (!rp.attachments.empty() && pick(rng, 2)) {
        auto& a = rp.attachments[pick(rng, uint32_t(rp.attachments.size()))];
        switch (pick(rng, 3)) {
          case 0:
            a.format = pick(rng, 185);
            return "attachment format " + std::to_string(a.format);
          case 1:
            a.samples = 1u << pick(rng, 7);
            return "attachment samples " + std::to_string(a.samples);
          default:
            a.final_layout = pick(rng, 9);
            return "attachment final layout " + std::to_string(a.final_layout);
        }
      }
      auto& sp = rp.subpasses[pick(rng, uint32_t(rp.subpasses.size()))];
      switch (pick(rng, 3)) {
        case 0:
          sp.colors.push_back({any_index(rng, rp.attachments.size()), pick(rng, 9)});
          return "add color reference";
        case 1:
          sp.depth_stencil = {any_index(rng, rp.attachments.size()), pick(rng, 9)};
          return "depth reference";
        default:
          if (!sp.colors.empty()) sp.colors.back().layout = pick(rng, 9);
          return "color layout";
      }
    }
    case 18:
      p.render_pass = any_index(rng, c.render_passes.size());
      p.subpass = pick(rng, 2);
      return "render pass " + std::to_string(p.render_pass);
    default: {
      if (c.samplers.empty()) return "none";
      auto& s = c.samplers[pick(rng, uint32_t(c.samplers.size()))];
      s.anisotropy_enable = pick(rng, 2), s.max_anisotropy = float(pick(rng, 64));
      s.compare_enable = pick(rng, 2), s.unnormalized_coordinates = pick(rng, 2);
      return "sampler";
    }
  }
}

// One edit of a declaration in a SPIR-V blob that keeps the module valid SPIR-V (a descriptor set or
// binding number, an entry point's execution model), so that only our checks against the stored
// records stand in the way. Block member offsets are not edited: a bad one makes invalid SPIR-V (layout
// rules), which only a full validator catches (see docs/api.md). The edited copy lives in `storage`,
// which must outlive the encoding.
//
// Or, with `undefined` set, a structural edit the reader must refuse (format/spirv_structure.cpp): a
// type, pointer or value operand made to name an id below the (raised) bound that nothing defines, the
// module that crashed the validation layer inside vkCreateComputePipelines.
std::string mutate_spirv(format::Contents& c, std::vector<uint32_t>& storage, Rng& rng, bool& undefined) {
  if (c.spirv.empty() || c.shaders.empty()) return "none";
  undefined = pick(rng, 3) == 0;
  // A blob a Vulkan shader record uses, which loading walks (the OpenGL block's are the GL runtime's).
  const uint32_t blob =
      undefined ? c.shaders[pick(rng, uint32_t(c.shaders.size()))].blob : pick(rng, uint32_t(c.spirv.size()));
  storage.assign(c.spirv[blob].begin(), c.spirv[blob].end());
  std::vector<size_t> targets;  // word positions worth editing
  for (size_t at = 5; at < storage.size() && (storage[at] >> 16) > 0; at += storage[at] >> 16) {
    const uint32_t count = storage[at] >> 16, op = storage[at] & 0xFFFF;
    if (undefined) {
      // Element and component types, a pointer's pointee, a variable's type, what a load reads.
      if ((op == 23 || op == 28 || op == 29) && count >= 3) targets.push_back(at + 2);
      if (op == 32 && count == 4) targets.push_back(at + 3);
      if ((op == 59 || op == 61) && count >= 4) targets.push_back(op == 59 ? at + 1 : at + 3);
      continue;
    }
    if (op == 71 && count == 4 && (storage[at + 2] == 33 || storage[at + 2] == 34)) targets.push_back(at + 3);
    if (op == 15) targets.push_back(at + 1);
  }
  if (targets.empty()) {
    undefined = false;
    return "none";
  }
  const size_t at = targets[pick(rng, uint32_t(targets.size()))];
  if (undefined) {
    storage[3] += 16;  // the bound: ids up to it may be used, and the new ones are defined by nothing
    storage[at] = storage[3] - 1 - pick(rng, 16);
  } else {
    storage[at] = pick(rng, 2) ? pick(rng, 6) : any_u32(rng) & 0xFFFF;
  }
  c.spirv[blob] = storage;
  return "SPIR-V blob " + std::to_string(blob) + " word " + std::to_string(at) + " = " +
         std::to_string(storage[at]);
}

class ResealedMutations : public VulkanTest {};

TEST_F(ResealedMutations, NeverCrashOrReachVulkanUnchecked) {
  std::vector<std::string> paths = corpus_archives();
  paths.push_back(STATEPACK_TEST_ARCHIVE);
  std::vector<Archive> seeds;
  for (const auto& path : paths) seeds.push_back(Archive::from_file(path).value());
  // A fixed count keeps the run reproducible; STATEPACK_MUTATIONS changes it for longer runs.
  const char* env = std::getenv("STATEPACK_MUTATIONS");
  const uint32_t total = env ? static_cast<uint32_t>(std::strtoul(env, nullptr, 10)) : 50000;
  size_t loaded = 0, unpacked = 0, rejected_at_load = 0, rejected_at_unpack = 0, refused_undefined = 0;
  size_t messages_before = 0;
  std::vector<std::string> noisy;
  const auto start = std::chrono::steady_clock::now();
  // STATEPACK_MUTANT=n replays mutant n alone (its description goes to stdout), to debug a failure.
  const char* only = std::getenv("STATEPACK_MUTANT");
  const char* from = std::getenv("STATEPACK_MUTANTS_FROM");  // replays a tail of the sequence
  const uint32_t first = only   ? static_cast<uint32_t>(std::strtoul(only, nullptr, 10))
                         : from ? static_cast<uint32_t>(std::strtoul(from, nullptr, 10))
                                : 0;
  for (uint32_t i = first; i < (only ? first + 1 : total); ++i) {
    Rng rng(i);
    const Archive& seed = seeds[i % seeds.size()];
    format::Contents c = detail::ArchiveAccess::contents(seed);
    // One pipeline per mutant keeps the driver's compile (the slow part) to one pipeline.
    if (!c.pipelines.empty()) {
      format::Pipeline kept = c.pipelines[pick(rng, uint32_t(c.pipelines.size()))];
      c.pipelines = {kept};
    }
    std::string what;
    std::vector<uint8_t> bytes;
    std::vector<uint32_t> spirv_storage;
    bool undefined_id = false;
    if (pick(rng, 6) == 0) {
      what = mutate_spirv(c, spirv_storage, rng, undefined_id) + "; ";
      bytes = format::encode(c);  // with the blob's content hash recomputed
    } else if (pick(rng, 3) != 0 && !c.pipelines.empty()) {
      for (uint32_t n = 1 + pick(rng, 2); n > 0; --n) what += mutate_structure(c, c.pipelines[0], rng) + "; ";
      bytes = format::encode(c);
    } else {
      bytes = format::encode(c);
      // Byte edits in the header, the section table and the records (before the SPIR-V data).
      uint32_t data_start = uint32_t(bytes.size());
      for (const auto& s : sections_of(bytes))
        if (s.tag == tag_of("DATA")) data_start = s.offset;
      for (uint32_t n = 1 + pick(rng, 4); n > 0; --n) {
        const uint32_t at = pick(rng, data_start);
        const uint8_t value = pick(rng, 2) ? uint8_t(rng()) : uint8_t(bytes[at] ^ (1u << pick(rng, 8)));
        what += "byte " + std::to_string(at) + " = " + std::to_string(value) + "; ";
        bytes[at] = value;
      }
    }
    reseal(bytes);
    if (only) {
      std::fprintf(stderr, "mutant %u: %s\n", i, what.c_str());
      std::ofstream(std::string(STATEPACK_TEST_OUTPUT_DIR) + "/mutant.spk", std::ios::binary)
          .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    }
    ForgedBytes forged(bytes);
    auto archive = Archive::from_memory(forged.span());
    if (!archive) {
      ++rejected_at_load;
      EXPECT_FALSE(archive.error().message.empty());
      if (undefined_id) {
        ++refused_undefined;
        // Outside functions a use must follow its definition; inside, the definition may come later.
        const std::string& m = archive.error().message;
        EXPECT_TRUE(m.find(" is not defined before its use") != std::string::npos ||
                    m.find(" is never defined") != std::string::npos)
            << "mutant " << i << ": " << what << m;
      }
      continue;
    }
    EXPECT_FALSE(undefined_id) << "mutant " << i << " (" << what << ") names an undefined id, and loads";
    ++loaded;
    {
      // The fixture's device enables no optional feature; say so, as applications must.
      const VkPhysicalDeviceFeatures enabled{};
      DeviceContext context{vk_->physical_device, vk_->device};
      context.enabled_features = &enabled;
      auto dearchiver = Dearchiver::create(context);
      ASSERT_TRUE(dearchiver);
      ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
      auto all = dearchiver->unpack_all(2);
      if (all) {
        ++unpacked;
      } else {
        ++rejected_at_unpack;
        EXPECT_NE(all.error().code, ErrorCode::vulkan_error)
            << "mutant " << i << ": " << what << all.error().message;
      }
    }
    const auto messages = vk_->validation_messages();
    if (messages.size() > messages_before) {
      noisy.push_back("mutant " + std::to_string(i) + " (" + what + "): " + messages[messages_before]);
      messages_before = messages.size();
    }
    // lavapipe keeps memory for every pipeline created until its device is destroyed (freed then, so
    // not a leak; 2.2 GB after 30,000 mutants): start a fresh device now and then, and give the freed
    // memory back (the driver's threads allocate from their own arenas, which glibc keeps otherwise).
    if (i % 250 == 249) {
      vk_->destroy_device();  // the layer reports objects a mutant left behind
      for (const auto& m : vk_->validation_messages()) ADD_FAILURE() << m;
      bootstrap::VulkanContextOptions options;
      options.validation = true;
      options.require_lavapipe = true;
      auto fresh = bootstrap::VulkanContext::create(options);
      ASSERT_TRUE(fresh) << fresh.error().message;
      vk_ = std::move(fresh.value());
      messages_before = 0;
      ::malloc_trim(0);
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "%u mutants in %.1f s: %zu rejected at load (%zu naming an undefined id), %zu loaded (%zu unpacked, "
      "%zu rejected at unpack)\n",
      total, seconds, rejected_at_load, refused_undefined, loaded, unpacked, rejected_at_unpack);
  for (const auto& n : noisy) ADD_FAILURE() << n;
  // The mutations must exercise both outcomes, or they test nothing.
  if (!only) {
    EXPECT_GT(rejected_at_load, total / 10);
    EXPECT_GT(unpacked, total / 20);
    EXPECT_GT(rejected_at_unpack, total / 20);
    EXPECT_GT(refused_undefined, total / 100);
  }
}

}  // namespace
}  // namespace statepack::testing
