#include "verify.hpp"

#include <algorithm>
#include <bit>
#include <ostream>

#include "format/archive_file.hpp"
#include "layout/format_support.hpp"
#include "notation/diagnostics.hpp"
#include "notation/enum_tables.hpp"
#include "pack/packer.hpp"
#include "runtime/archive_access.hpp"
#include "statepack/bootstrap/vulkan_context.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::packager {
namespace {

const char* kind_name(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::graphics_pipeline:
      return "graphics pipeline";
    case ObjectKind::compute_pipeline:
      return "compute pipeline";
    case ObjectKind::resource_signature:
      return "resource signature";
    case ObjectKind::render_pass:
      return "render pass";
    case ObjectKind::shader:
      return "shader";
  }
  return "object";
}

// `patched_slots` receives the render targets the archive leaves to run time (UNKNOWN, or absent while
// the pixel shader writes them), which the application must set: verify shows them.
Result<void> unpack_one(Dearchiver& dearchiver, const ObjectInfo& object, VkFormat color_format,
                        std::vector<uint32_t>& patched_slots) {
  switch (object.kind) {
    case ObjectKind::graphics_pipeline: {
      // A render target left UNKNOWN is patched at run time (a swapchain format): verify it with one.
      auto patched = dearchiver.unpack_graphics(object.name, [&](PatchableState& s) {
        // Targets the notation leaves to run time (the pixel shader writes more than it gives) are
        // added as the application's callback would add them.
        const uint32_t written = uint32_t(32 - std::countl_zero(s.written_color_targets));
        if (written > s.color_count && written <= s.color_formats.size()) s.color_count = written;
        for (uint32_t i = 0; i < s.color_count && i < s.color_formats.size(); ++i)
          if (s.color_formats[i] == VK_FORMAT_UNDEFINED) {
            s.color_formats[i] = color_format;
            patched_slots.push_back(i);
          }
      });
      if (!patched) return patched.error();
      return {};
    }
    case ObjectKind::compute_pipeline:
      if (auto r = dearchiver.unpack_compute(object.name); !r) return r.error();
      return {};
    case ObjectKind::resource_signature:
      if (auto r = dearchiver.unpack_signature(object.name); !r) return r.error();
      return {};
    case ObjectKind::render_pass:
      if (auto r = dearchiver.unpack_render_pass(object.name); !r) return r.error();
      return {};
    case ObjectKind::shader:
      if (auto r = dearchiver.unpack_shader(object.name); !r) return r.error();
      return {};
  }
  return {};
}

}  // namespace

std::optional<VkFormat> parse_vk_format(const std::string& name) {
  std::string bare = name.starts_with("VK_FORMAT_") ? name.substr(10) : name;
  // The notation's names (RGBA8_UNORM) first, then Vulkan's own for the formats the notation has.
  for (const auto& [text, value] : kTextureFormats)
    if (text == bare && value != VK_FORMAT_UNDEFINED && value != kUnsupportedValue) return VkFormat(value);
  return std::nullopt;
}

int run_verify(const VerifyOptions& options, std::ostream& out, std::ostream& err) {
  bootstrap::VulkanContextOptions vk_options;
  vk_options.validation = options.validation;
  vk_options.validation_if_present = true;
  vk_options.device_index = options.device_index;
  vk_options.enable_supported_features = true;
  auto vk = bootstrap::VulkanContext::create(vk_options);
  if (!vk) {
    err << "statepack: error: cannot create a Vulkan device: " << printable(vk.error().message) << '\n';
    return kExitIoError;
  }
  out << "device: " << printable((*vk)->device_name) << " (" << printable((*vk)->driver_name) << ")"
      << ((*vk)->validation_enabled ? ", validation layer on" : "") << '\n';
  if (options.validation && !(*vk)->validation_enabled)
    err << "statepack: note: the Vulkan validation layer is not installed; objects are only created "
           "(apt-get install vulkan-validationlayers)\n";

  DeviceContext context = (*vk)->device_context();
  std::optional<PipelineCacheLoad> cache;
  if (options.cache) {
    auto loaded = load_pipeline_cache(context, *options.cache);
    if (!loaded) {
      err << "statepack: error: " << printable(loaded.error().message) << '\n';
      return kExitIoError;
    }
    cache = *loaded;
    context.pipeline_cache = cache->cache;
    if (!cache->reused && !cache->reason.empty())
      out << "pipeline cache: starting empty (" << printable(cache->reason) << ")\n";
  }

  int exit_code = kExitSuccess;
  size_t messages_seen = 0;
  auto new_messages = [&] {
    auto all = (*vk)->validation_messages();
    std::vector<std::string> fresh(all.begin() + std::ptrdiff_t(std::min(messages_seen, all.size())),
                                   all.end());
    messages_seen = all.size();
    return fresh;
  };
  for (const auto& path : options.archives) {
    auto archive = Archive::from_file(path);
    if (!archive) {
      err << "statepack: error: " << printable(archive.error().message) << '\n';
      exit_code = std::max(exit_code, int(kExitIoError));
      continue;
    }
    // Archive checks what Vulkan uses; the OpenGL block, which verify does not create, is checked too.
    if (auto gl = format::check_opengl(detail::ArchiveAccess::contents(*archive), path.string()); !gl) {
      err << "statepack: error: " << printable(gl.error().message) << '\n';
      exit_code = std::max(exit_code, int(kExitInputError));
      continue;
    }
    std::vector<ObjectInfo> objects = archive->objects();
    size_t ok = 0;
    {
      auto dearchiver = Dearchiver::create(context);
      if (!dearchiver || !dearchiver->add_archive(std::move(*archive))) {
        err << "statepack: error: " << printable(path.string()) << ": cannot create the dearchiver\n";
        exit_code = std::max(exit_code, int(kExitInputError));
        continue;
      }
      for (const ObjectInfo& object : objects) {
        std::vector<uint32_t> patched_slots;
        auto unpacked = unpack_one(*dearchiver, object, options.color_format, patched_slots);
        auto messages = new_messages();
        std::string what = std::string(kind_name(object.kind)) + " '" + printable(object.name) + "'";
        if (!patched_slots.empty()) {
          what += " (render target";
          for (size_t i = 0; i < patched_slots.size(); ++i)
            what += (i ? ", " : patched_slots.size() > 1 ? "s " : " ") + std::to_string(patched_slots[i]);
          what += ", set at run time: verified as " + format_name(options.color_format) + ")";
        }
        // Performance warnings are advice: the object is valid, and is reported ok with them.
        const bool only_advice = std::all_of(messages.begin(), messages.end(), [](const std::string& m) {
          return m.starts_with(bootstrap::kPerformanceWarning);
        });
        if (unpacked && only_advice) {
          out << "ok     " << what << '\n';
          for (const auto& m : messages) out << "         warning: " << printable(m) << '\n';
          ++ok;
          continue;
        }
        exit_code = std::max(exit_code, int(kExitInputError));
        out << "FAILED " << what << ": "
            << (unpacked ? "validation messages" : printable(unpacked.error().message)) << '\n';
        for (const auto& m : messages) out << "         " << printable(m) << '\n';
      }
    }  // the dearchiver destroys its objects here; the layer reports anything left behind
    if (auto leaks = new_messages(); !leaks.empty()) {
      exit_code = std::max(exit_code, int(kExitInputError));
      for (const auto& m : leaks)
        out << "FAILED " << printable(path.string()) << ": " << printable(m) << '\n';
    }
    out << printable(path.string()) << ": " << ok << " of " << objects.size() << " objects ok\n";
  }
  if (cache) {
    if (auto saved = save_pipeline_cache(context, cache->cache, *options.cache); !saved) {
      err << "statepack: error: " << printable(saved.error().message) << '\n';
      exit_code = std::max(exit_code, int(kExitIoError));
    } else {
      out << "pipeline cache: written to " << printable(options.cache->string()) << '\n';
    }
    vkDestroyPipelineCache((*vk)->device, cache->cache, nullptr);
  }
  (*vk)->destroy_device();
  if (auto last = new_messages(); !last.empty()) {
    exit_code = std::max(exit_code, int(kExitInputError));
    for (const auto& m : last) out << "FAILED device teardown: " << printable(m) << '\n';
  }
  return exit_code;
}

}  // namespace statepack::packager
