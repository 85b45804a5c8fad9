// Dearchiver: finds archived objects by name and keeps what it unpacked. The Vulkan objects pipelines
// share are the ObjectCache's; turning an archived pipeline into create-info structs is the Planner's.
#include "statepack/dearchiver.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <unordered_map>

#include "api_guard.hpp"
#include "archive_access.hpp"
#include "device_limits.hpp"
#include "format/archive_format.hpp"
#include "object_cache.hpp"
#include "pipeline_plan.hpp"
#include "support/parallel_for.hpp"
#include "support/suggest.hpp"
#include "variant_key.hpp"
#include "vk_result_string.hpp"
#include "vulkan_functions.hpp"

namespace statepack {
using namespace detail;  // the runtime's internals: this file defines the public API on top of them

const BindingInfo* UnpackedPipeline::find_binding(std::string_view resource_name) const {
  for (const auto& b : bindings)
    if (b.name == resource_name) return &b;
  return nullptr;
}

struct Dearchiver::State {
  DeviceContext context;
  DeviceCaps caps;  // limits and formats, checked before any vkCreate*
  // Enabled (as the caller says) or supported features, every structure; assigned in create(), so the
  // references below stay bound to it.
  EnabledFeatures enabled;
  std::vector<Archive> archives;
  ObjectCache cache{context, caps, enabled, archives};  // what pipelines share
  Planner planner{context, caps, enabled.core(), cache};
  std::deque<UnpackedSignature> signatures;
  std::map<std::pair<size_t, uint32_t>, const UnpackedSignature*> signature_by_layout;
  std::deque<UnpackedPipeline> pipelines;                                  // stable addresses
  std::map<std::string, const UnpackedPipeline*, std::less<>> unmodified;  // cache by name
  std::map<std::string, const UnpackedPipeline*> variants;                 // patched, by variant_key
  struct Place {
    size_t slot;                                                       // in `pipelines`
    std::map<std::string, const UnpackedPipeline*>::iterator variant;  // variants.end(): not a variant
  };
  std::unordered_map<const UnpackedPipeline*, Place> place_of;  // live pipelines, for release()
  std::vector<size_t> free_slots;                               // places of released ones
  std::mutex mutex;

  ~State() {  // the pipelines go before the objects they were made from (the cache, a member)
    for (auto& p : pipelines) caps.vk.vkDestroyPipeline(context.device, p.pipeline, context.allocator);
  }

  const format::Contents& contents(size_t archive) const {
    return detail::ArchiveAccess::contents(archives[archive]);
  }

  // Names of the given kinds across every archive, for listings and "did you mean".
  std::vector<std::string> names_of(std::initializer_list<ObjectKind> kinds) const {
    std::vector<std::string> names;
    for (const auto& a : archives)
      for (const auto& [name, kind] : a.objects())
        if (std::find(kinds.begin(), kinds.end(), kind) != kinds.end()) names.push_back(name);
    return names;
  }
  std::vector<std::string> all_names() const {
    return names_of({ObjectKind::graphics_pipeline, ObjectKind::compute_pipeline});
  }

  Result<ArchivedPipeline> find(std::string_view name, format::PipelineKind kind) const {
    for (size_t i = 0; i < archives.size(); ++i) {
      const auto& list = contents(i).pipelines;  // sorted by name (checked on load)
      auto it = std::lower_bound(list.begin(), list.end(), name,
                                 [](const format::Pipeline& p, std::string_view n) { return p.name < n; });
      if (it == list.end() || it->name != name) continue;
      if (it->kind != kind) {
        const char* actual = it->kind == format::PipelineKind::compute ? "compute" : "graphics";
        const char* wanted = kind == format::PipelineKind::compute ? "compute" : "graphics";
        return Error{ErrorCode::wrong_type, "pipeline '" + std::string(name) + "' is a " + actual +
                                                " pipeline, not a " + wanted + " pipeline"};
      }
      return ArchivedPipeline{i, &*it};
    }
    auto names = all_names();
    return Error{ErrorCode::not_found, "no pipeline named '" + std::string(name) + "' in " +
                                           std::to_string(archives.size()) + " loaded archive(s)" +
                                           did_you_mean(name, names)};
  }

  // The first archive that has an object of that name; `names` lists them all for suggestions.
  template <class Find>
  std::optional<std::pair<size_t, uint32_t>> find_named(Find&& find_in) const {
    for (size_t i = 0; i < archives.size(); ++i)
      if (auto index = find_in(contents(i))) return std::pair{i, *index};
    return std::nullopt;
  }

  // Creates the pipeline of a plan; safe to call for different plans on several threads.
  Result<void> create(Plan& plan) const {
    VkResult r =
        plan.out.bind_point == VK_PIPELINE_BIND_POINT_COMPUTE
            ? caps.vk.vkCreateComputePipelines(context.device, context.pipeline_cache, 1, &plan.compute,
                                               context.allocator, &plan.out.pipeline)
            : caps.vk.vkCreateGraphicsPipelines(context.device, context.pipeline_cache, 1, &plan.graphics,
                                                context.allocator, &plan.out.pipeline);
    if (r != VK_SUCCESS)
      return vulkan_failure(plan.out.bind_point == VK_PIPELINE_BIND_POINT_COMPUTE
                                ? "vkCreateComputePipelines"
                                : "vkCreateGraphicsPipelines",
                            r, plan.out.name);
    return {};
  }

  // Keeps a created pipeline (in a released one's place when there is one); `key`: its variant key.
  const UnpackedPipeline* keep(Plan& plan, std::string key = {}) {
    size_t slot = pipelines.size();
    if (!free_slots.empty()) {
      slot = free_slots.back();
      free_slots.pop_back();
      pipelines[slot] = std::move(plan.out);
    } else {
      pipelines.push_back(std::move(plan.out));
    }
    const UnpackedPipeline* kept = &pipelines[slot];
    if (plan.cacheable) unmodified.emplace(kept->name, kept);
    auto variant = key.empty() ? variants.end() : variants.emplace(std::move(key), kept).first;
    place_of.emplace(kept, Place{slot, variant});
    return kept;
  }

  // The variant made before with the same settled state, if any.
  const UnpackedPipeline* earlier_variant(const std::string& key) const {
    auto it = variants.find(key);
    return it == variants.end() ? nullptr : it->second;
  }

  Result<void> release(const UnpackedPipeline* pipeline) {
    auto it = place_of.find(pipeline);
    if (it == place_of.end())
      return Error{ErrorCode::invalid_argument,
                   "Dearchiver::release: the pipeline is not one this Dearchiver holds (released already, or "
                   "from another Dearchiver)"};
    const Place place = it->second;
    place_of.erase(it);
    if (auto u = unmodified.find(pipeline->name); u != unmodified.end() && u->second == pipeline)
      unmodified.erase(u);
    if (place.variant != variants.end()) variants.erase(place.variant);
    const size_t slot = place.slot;
    caps.vk.vkDestroyPipeline(context.device, pipelines[slot].pipeline, context.allocator);
    pipelines[slot] = UnpackedPipeline{};  // VK_NULL_HANDLE: the destructor skips it
    free_slots.push_back(slot);
    return {};
  }

  // Cached, or planned, created and kept.
  Result<const UnpackedPipeline*> unpack(std::string_view name, format::PipelineKind kind,
                                         const ModifyCallback& modify) {
    const VkPipelineBindPoint bind_point = kind == format::PipelineKind::compute
                                               ? VK_PIPELINE_BIND_POINT_COMPUTE
                                               : VK_PIPELINE_BIND_POINT_GRAPHICS;
    if (!modify)
      if (auto it = unmodified.find(name); it != unmodified.end() && it->second->bind_point == bind_point)
        return it->second;
    auto found = find(name, kind);
    if (!found) return found.error();
    auto plan = kind == format::PipelineKind::compute ? planner.plan_compute(*found, modify)
                                                      : planner.plan_graphics(*found, modify);
    if (!plan) return plan.error();
    // A patched pipeline whose settled state equals an earlier one's is that pipeline.
    std::string key = modify ? variant_key(name, **plan) : std::string();
    if (!key.empty())
      if (const UnpackedPipeline* earlier = earlier_variant(key)) return earlier;
    if (auto created = create(**plan); !created) return created.error();
    return keep(**plan, std::move(key));
  }
};

Dearchiver::Dearchiver(std::unique_ptr<State> state) : state_(std::move(state)) {}
Dearchiver::Dearchiver(Dearchiver&&) noexcept = default;
Dearchiver& Dearchiver::operator=(Dearchiver&&) noexcept = default;
Dearchiver::~Dearchiver() = default;

Result<Dearchiver> Dearchiver::create(const DeviceContext& context) {
  return api_guard("Dearchiver::create", [&]() -> Result<Dearchiver> {
    if (context.device == VK_NULL_HANDLE || context.physical_device == VK_NULL_HANDLE)
      return Error{ErrorCode::invalid_argument, "Dearchiver::create needs a VkPhysicalDevice and a VkDevice"};
    auto functions = load_vulkan_functions(context, "Dearchiver::create");
    if (!functions) return functions.error();
    auto state = std::make_unique<State>();
    state->context = context;
    state->caps.physical_device = context.physical_device;
    state->caps.vk = *functions;
    state->caps.vk.vkGetPhysicalDeviceProperties(context.physical_device, &state->caps.properties);
    state->enabled = EnabledFeatures::gather(context, state->caps);
    state->context.enabled_feature_chain = nullptr;  // read: the application may free it now
    state->context.enabled_extensions = nullptr;
    return Dearchiver(std::move(state));
  });
}

Result<void> Dearchiver::add_archive(Archive archive) {
  return api_guard("Dearchiver::add_archive", [&]() -> Result<void> {
    std::lock_guard lock(state_->mutex);
    state_->archives.push_back(std::move(archive));
    return {};
  });
}

Result<void> Dearchiver::release(const UnpackedPipeline* pipeline) {
  return api_guard("Dearchiver::release", [&]() -> Result<void> {
    std::lock_guard lock(state_->mutex);
    return state_->release(pipeline);
  });
}

std::vector<std::string> Dearchiver::pipeline_names() const {
  std::lock_guard lock(state_->mutex);
  return state_->all_names();
}

Result<const UnpackedPipeline*> Dearchiver::unpack_compute(std::string_view name,
                                                           const ModifyCallback& modify) {
  return api_guard("Dearchiver::unpack_compute", [&]() -> Result<const UnpackedPipeline*> {
    std::lock_guard lock(state_->mutex);
    return state_->unpack(name, format::PipelineKind::compute, modify);
  });
}

Result<const UnpackedPipeline*> Dearchiver::unpack_graphics(std::string_view name,
                                                            const ModifyCallback& modify) {
  return api_guard("Dearchiver::unpack_graphics", [&]() -> Result<const UnpackedPipeline*> {
    std::lock_guard lock(state_->mutex);
    return state_->unpack(name, format::PipelineKind::graphics, modify);
  });
}

Result<std::vector<const UnpackedPipeline*>> Dearchiver::unpack_all(uint32_t threads) {
  return unpack_all(PatchCallback{}, threads);
}

Result<std::vector<const UnpackedPipeline*>> Dearchiver::unpack_all(const PatchCallback& patch,
                                                                    uint32_t threads) {
  return api_guard("Dearchiver::unpack_all", [&]() -> Result<std::vector<const UnpackedPipeline*>> {
    auto pipelines = unpack_all_pipelines(threads, patch);
    if (!pipelines) return pipelines.error();
    // The other named objects too, so that everything is ready.
    std::vector<ObjectInfo> objects;
    {
      std::lock_guard lock(state_->mutex);
      for (const auto& archive : state_->archives) {
        auto more = archive.objects();
        objects.insert(objects.end(), more.begin(), more.end());
      }
    }
    for (const auto& [name, kind] : objects) {
      Result<void> ok;
      if (kind == ObjectKind::resource_signature) {
        if (auto r = unpack_signature(name); !r) ok = r.error();
      } else if (kind == ObjectKind::render_pass) {
        if (auto r = unpack_render_pass(name); !r) ok = r.error();
      } else if (kind == ObjectKind::shader) {
        if (auto r = unpack_shader(name); !r) ok = r.error();
      }
      if (!ok) return ok.error();
    }
    return pipelines;
  });
}

Result<std::vector<const UnpackedPipeline*>> Dearchiver::unpack_all_pipelines(uint32_t threads,
                                                                              const PatchCallback& patch) {
  std::lock_guard lock(state_->mutex);
  // Plan every pipeline not yet unpacked (serially: shared objects are created once), then create the
  // pipelines on `threads` threads: the driver's compile is the expensive part.
  std::vector<std::unique_ptr<Plan>> plans;
  std::vector<std::string> keys;  // each plan's variant key (patched), else empty
  std::vector<const UnpackedPipeline*> done;
  std::set<std::string, std::less<>> seen;
  for (size_t a = 0; a < state_->archives.size(); ++a) {
    for (const auto& p : state_->contents(a).pipelines) {
      if (!seen.insert(p.name).second) continue;  // the earliest archive wins
      if (!patch)  // a patch callback sees every pipeline, so nothing made earlier is reused then
        if (auto it = state_->unmodified.find(p.name); it != state_->unmodified.end()) {
          done.push_back(it->second);
          continue;
        }
      const ArchivedPipeline found{a, &p};
      const bool compute = p.kind == format::PipelineKind::compute;
      // The single-object path's callback, told which pipeline it patches: the patched state goes
      // through the same checks as unpack_graphics/unpack_compute with a modify callback.
      ModifyCallback modify;
      if (patch) {
        const ObjectInfo object{p.name,
                                compute ? ObjectKind::compute_pipeline : ObjectKind::graphics_pipeline};
        modify = [&patch, object](PatchableState& s) { patch(object, s); };
      }
      auto plan = compute ? state_->planner.plan_compute(found, modify)
                          : state_->planner.plan_graphics(found, modify);
      if (!plan) return plan.error();
      if (patch) {
        std::string key = variant_key(p.name, **plan);
        if (const UnpackedPipeline* earlier = state_->earlier_variant(key)) {
          done.push_back(earlier);
          continue;
        }
        keys.push_back(std::move(key));
      } else {
        keys.emplace_back();
      }
      plans.push_back(std::move(plan.value()));
    }
  }
  std::vector<std::optional<Error>> failures(plans.size());
  parallel_for(plans.size(), threads, [&](size_t i) {
    if (auto created = state_->create(*plans[i]); !created) failures[i] = created.error();
  });
  std::optional<Error> first_failure;
  for (size_t i = 0; i < plans.size(); ++i) {
    if (failures[i]) {
      if (!first_failure) first_failure = failures[i];
      continue;
    }
    done.push_back(
        state_->keep(*plans[i], std::move(keys[i])));  // destroyed with the dearchiver even on failure
  }
  if (first_failure) return *first_failure;
  return done;
}

Result<const UnpackedSignature*> Dearchiver::unpack_signature(std::string_view name) {
  return api_guard("Dearchiver::unpack_signature", [&]() -> Result<const UnpackedSignature*> {
    std::lock_guard lock(state_->mutex);
    auto found = state_->find_named([&](const format::Contents& c) -> std::optional<uint32_t> {
      for (uint32_t i = 0; i < c.set_layouts.size(); ++i)
        if (!c.set_layouts[i].name.empty() && c.set_layouts[i].name == name) return i;
      return std::nullopt;
    });
    if (!found) {
      return Error{ErrorCode::not_found,
                   "no resource signature named '" + std::string(name) + "'" +
                       did_you_mean(name, state_->names_of({ObjectKind::resource_signature}))};
    }
    if (auto it = state_->signature_by_layout.find(*found); it != state_->signature_by_layout.end())
      return it->second;
    auto layout = state_->cache.set_layout(found->first, found->second, name);
    if (!layout) return layout.error();
    const format::SetLayout& stored = state_->contents(found->first).set_layouts[found->second];
    UnpackedSignature& sig = state_->signatures.emplace_back();
    sig.name = stored.name;
    sig.layout = *layout;
    sig.set = stored.binding_index;
    for (const auto& b : stored.bindings)
      sig.bindings.push_back({b.name, stored.binding_index, b.binding,
                              static_cast<VkDescriptorType>(b.descriptor_type), b.count, b.stage_flags,
                              state_->cache.immutable_sampler_of(found->first, b)});
    state_->signature_by_layout.emplace(*found, &sig);
    return &sig;
  });
}

Result<VkRenderPass> Dearchiver::unpack_render_pass(std::string_view name) {
  return api_guard("Dearchiver::unpack_render_pass", [&]() -> Result<VkRenderPass> {
    std::lock_guard lock(state_->mutex);
    auto found = state_->find_named([&](const format::Contents& c) -> std::optional<uint32_t> {
      for (uint32_t i = 0; i < c.render_passes.size(); ++i)
        if (c.render_passes[i].name == name) return i;
      return std::nullopt;
    });
    if (!found) {
      return Error{ErrorCode::not_found, "no render pass named '" + std::string(name) + "'" +
                                             did_you_mean(name, state_->names_of({ObjectKind::render_pass}))};
    }
    return state_->cache.render_pass(found->first, found->second);
  });
}

Result<UnpackedShader> Dearchiver::unpack_shader(std::string_view name) {
  return api_guard("Dearchiver::unpack_shader", [&]() -> Result<UnpackedShader> {
    std::lock_guard lock(state_->mutex);
    auto found = state_->find_named([&](const format::Contents& c) -> std::optional<uint32_t> {
      auto it = std::lower_bound(c.standalone_shaders.begin(), c.standalone_shaders.end(), name,
                                 [&](uint32_t s, std::string_view n) { return c.shaders[s].name < n; });
      if (it != c.standalone_shaders.end() && c.shaders[*it].name == name) return *it;
      return std::nullopt;
    });
    if (!found) {
      return Error{ErrorCode::not_found, "no standalone shader named '" + std::string(name) + "'" +
                                             did_you_mean(name, state_->names_of({ObjectKind::shader}))};
    }
    const format::Shader& shader = state_->contents(found->first).shaders[found->second];
    auto module = state_->cache.module(found->first, shader.blob, shader.name);
    if (!module) return module.error();
    return UnpackedShader{shader.name, *module, static_cast<VkShaderStageFlagBits>(shader.stage),
                          shader.entry_point};
  });
}

}  // namespace statepack
