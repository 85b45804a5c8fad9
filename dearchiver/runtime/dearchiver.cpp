// Dearchiver: finds archived objects by name and keeps what it unpacked. The Vulkan objects pipelines
// share are the ObjectCache's; turning an archived pipeline into create-info structs is the Planner's;
// unpack_all and its jobs are unpack_job.cpp's, the variants file variants.cpp's.
#include "statepack/dearchiver.hpp"

#include "support/failure.hpp"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>

#include "api_guard.hpp"
#include "archive_access.hpp"
#include "dearchiver_state.hpp"
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

Dearchiver::State::~State() {
  // Jobs first: their threads use everything below. Each cancels what it has not begun and joins.
  for (auto& weak : jobs)
    if (auto job = weak.lock()) stop_job(*job, true);
  // The pipelines go before the objects they were made from (the cache, a member).
  for (auto& p : pipelines) caps.vk.vkDestroyPipeline(context.device, p.pipeline, context.allocator);
  for (auto& r : retired) caps.vk.vkDestroyPipeline(context.device, r.pipeline, context.allocator);
}

const format::Contents& Dearchiver::State::contents(size_t archive) const {
  return detail::ArchiveAccess::contents(archives[archive]);
}

std::vector<std::string> Dearchiver::State::names_of(std::initializer_list<ObjectKind> kinds) const {
  std::vector<std::string> names;
  for (size_t a : active)
    for (const auto& [name, kind] : archives[a].objects())
      if (std::find(kinds.begin(), kinds.end(), kind) != kinds.end()) names.push_back(name);
  return names;
}

std::vector<std::string> Dearchiver::State::pipeline_names() const {
  return names_of({ObjectKind::graphics_pipeline, ObjectKind::compute_pipeline});
}

Result<ArchivedPipeline> Dearchiver::State::find(std::string_view name, format::PipelineKind kind) const {
  for (size_t i : active) {
    const format::Pipeline* it = format::find_by_name(contents(i).pipelines, name);
    if (!it) continue;
    if (it->kind != kind) return not_of_kind(name, it->kind);
    return ArchivedPipeline{i, it};
  }
  return not_found(name);
}

Error Dearchiver::State::not_of_kind(std::string_view name, format::PipelineKind actual) {
  const char* is = actual == format::PipelineKind::compute ? "compute" : "graphics";
  const char* wanted = actual == format::PipelineKind::compute ? "graphics" : "compute";
  return detail::failure(ErrorCode::wrong_type, "pipeline '" + std::string(name) + "' is a " + is +
                                                    " pipeline, not a " + wanted + " pipeline");
}

Error Dearchiver::State::not_found(std::string_view name) const {
  auto names = pipeline_names();
  return detail::failure(ErrorCode::not_found, "no pipeline named '" + std::string(name) + "' in " +
                                                   std::to_string(active.size()) + " loaded archive(s)" +
                                                   did_you_mean(name, names));
}

Result<void> Dearchiver::State::create(Plan& plan) const {
  const bool compute = plan.out.bind_point == VK_PIPELINE_BIND_POINT_COMPUTE;
  // Feedback for the pipeline as a whole (no per-stage array: Vulkan allows 0 stages).
  if (creation_feedback) {
    plan.feedback_info.pPipelineCreationFeedback = &plan.feedback;
    const void*& next = compute ? plan.compute.pNext : plan.graphics.pNext;
    if (next != &plan.feedback_info) {
      plan.feedback_info.pNext = next;
      next = &plan.feedback_info;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  VkResult r = compute
                   ? caps.vk.vkCreateComputePipelines(context.device, context.pipeline_cache, 1,
                                                      &plan.compute, context.allocator, &plan.out.pipeline)
                   : caps.vk.vkCreateGraphicsPipelines(context.device, context.pipeline_cache, 1,
                                                       &plan.graphics, context.allocator, &plan.out.pipeline);
  PipelineCreation& creation = plan.out.creation;
  creation.time = std::chrono::steady_clock::now() - start;
  if (creation_feedback && (plan.feedback.flags & VK_PIPELINE_CREATION_FEEDBACK_VALID_BIT)) {
    creation.feedback = true;
    creation.driver_time = std::chrono::nanoseconds(plan.feedback.duration);
    creation.cache_hit =
        plan.feedback.flags & VK_PIPELINE_CREATION_FEEDBACK_APPLICATION_PIPELINE_CACHE_HIT_BIT;
  }
  if (r != VK_SUCCESS)
    return vulkan_failure(compute ? "vkCreateComputePipelines" : "vkCreateGraphicsPipelines", r,
                          plan.out.name);
  return {};
}

Dearchiver::State::Record& Dearchiver::State::record_of(const ArchivedPipeline& p) {
  return records[p.archive][size_t(p.pipeline - contents(p.archive).pipelines.data())];
}

const UnpackedPipeline* Dearchiver::State::keep(Plan& plan, std::string key) {
  // Whatever may throw (every allocation) comes first, each step undone if a later one throws, and the
  // pipeline is published (moved into its place, cached) only once nothing can fail: the caller destroys
  // the VkPipeline when this throws, so nothing may be left pointing at it.
  const bool reuse = !free_slots.empty();
  const size_t slot = reuse ? free_slots.back() : pipelines.size();
  if (!reuse) pipelines.emplace_back();  // an empty place (VK_NULL_HANDLE: the destructor skips it)
  const UnpackedPipeline* kept = &pipelines[slot];
  auto variant = variants.end();
  std::optional<std::map<std::string, size_t>::iterator> new_key;
  size_t recorded_at = SIZE_MAX;
  bool state_recorded = false;
  std::unordered_map<const UnpackedPipeline*, Place>::iterator place;
  try {
    if (!key.empty()) {
      auto [at, inserted] = recorded_keys.emplace(key, recorded.size());
      if (inserted) new_key = at;
      if (new_key) {
        recorded.push_back({plan.source, plan.out.bind_point, plan.state, false, key});
        state_recorded = true;
      } else {
        // Made before and released (or its pipeline gone in a reload and back): this state, from this
        // archive, is what the entry records now. Built first, so that a throw changes nothing.
        Recorded fresh{plan.source, plan.out.bind_point, plan.state, false, key};
        recorded[at->second] = std::move(fresh);
      }
      recorded_at = at->second;
      variant = variants.emplace(std::move(key), kept).first;
    }
    place = place_of.emplace(kept, Place{slot, variant, nullptr, plan.source, recorded_at}).first;
  } catch (...) {
    if (variant != variants.end()) variants.erase(variant);
    if (state_recorded) recorded.pop_back();
    if (new_key) recorded_keys.erase(*new_key);
    if (!reuse) pipelines.pop_back();
    throw;
  }
  // Nothing below allocates.
  if (reuse) free_slots.pop_back();
  pipelines[slot] = std::move(plan.out);
  if (plan.cacheable) {
    Record& record = record_of(plan.source);
    if (!record.unmodified) {  // made twice (a cancelled job's): the first stays cached
      record.unmodified = kept;
      place->second.record = &record;
    }
  }
  return kept;
}

const UnpackedPipeline* Dearchiver::State::earlier_variant(const std::string& key) const {
  auto it = variants.find(key);
  return it == variants.end() ? nullptr : it->second;
}

Result<void> Dearchiver::State::release(const UnpackedPipeline* pipeline) {
  auto it = place_of.find(pipeline);
  if (it == place_of.end())
    return detail::failure(
        ErrorCode::invalid_argument,
        "Dearchiver::release: the pipeline is not one this Dearchiver holds (released already, or "
        "from another Dearchiver)");
  const Place place = it->second;
  place_of.erase(it);
  if (place.record) place.record->unmodified = nullptr;
  if (place.variant != variants.end()) variants.erase(place.variant);
  const size_t slot = place.slot;
  caps.vk.vkDestroyPipeline(context.device, pipelines[slot].pipeline, context.allocator);
  pipelines[slot] = UnpackedPipeline{};  // VK_NULL_HANDLE: the destructor skips it
  free_slots.push_back(slot);
  return {};
}

namespace {

// Waits, without the Dearchiver's lock, for a pipeline a job is creating. nullopt: the job was cancelled
// before it began that pipeline (the caller makes it itself).
std::optional<Result<const UnpackedPipeline*>> wait_for(std::unique_lock<std::mutex>& lock, SlotSync& sync,
                                                        std::shared_ptr<PipelineSlot> slot) {
  lock.unlock();
  std::unique_lock wait(sync.mutex);
  sync.finished.wait(wait, [&] { return slot->finished; });
  wait.unlock();
  lock.lock();
  if (slot->cancelled) return std::nullopt;
  if (slot->error) return *slot->error;
  return slot->pipeline;
}

}  // namespace

Result<const UnpackedPipeline*> Dearchiver::State::unpack(std::unique_lock<std::mutex>& lock,
                                                          std::string_view name, format::PipelineKind kind,
                                                          const ModifyCallback& modify) {
  for (;;) {  // again when a job this waited for was cancelled
    if (!modify) {
      auto found = find(name, kind);
      if (!found) return found.error();
      Record& record = record_of(*found);
      if (record.unmodified) return record.unmodified;
      if (record.creating) {
        if (auto made = wait_for(lock, *sync, record.creating)) return *made;
        continue;
      }
    }
    break;
  }
  for (;;) {
    auto found = find(name, kind);
    if (!found) return found.error();
    auto plan = kind == format::PipelineKind::compute ? planner.plan_compute(*found, modify)
                                                      : planner.plan_graphics(*found, modify);
    if (!plan) return plan.error();
    // A patched pipeline whose settled state equals an earlier one's is that pipeline.
    std::string key = modify ? variant_key(name, **plan) : std::string();
    if (!key.empty()) {
      if (const UnpackedPipeline* earlier = earlier_variant(key)) return earlier;
      if (auto it = creating_variants.find(key); it != creating_variants.end()) {
        if (auto made = wait_for(lock, *sync, it->second)) return *made;
        continue;  // cancelled: plan it again (the callback runs again)
      }
    }
    if (auto created = create(**plan); !created) return created.error();
    return keep(**plan, std::move(key));
  }
}

Dearchiver::Dearchiver(std::unique_ptr<State> state) : state_(std::move(state)) {}
Dearchiver::Dearchiver(Dearchiver&&) noexcept = default;
Dearchiver& Dearchiver::operator=(Dearchiver&&) noexcept = default;
Dearchiver::~Dearchiver() = default;

Result<Dearchiver> Dearchiver::create(const DeviceContext& context) {
  return api_guard("Dearchiver::create", [&]() -> Result<Dearchiver> {
    if (context.device == VK_NULL_HANDLE || context.physical_device == VK_NULL_HANDLE)
      return detail::failure(ErrorCode::invalid_argument,
                             "Dearchiver::create needs a VkPhysicalDevice and a VkDevice");
    auto functions = load_vulkan_functions(context, "Dearchiver::create");
    if (!functions) return functions.error();
    auto state = std::make_unique<State>();
    state->context = context;
    state->caps.physical_device = context.physical_device;
    state->caps.vk = *functions;
    state->caps.vk.vkGetPhysicalDeviceProperties(context.physical_device, &state->caps.properties);
    // From here on the version is what the application may use, not what the device could do.
    state->caps.properties.apiVersion = effective_api_version(context, state->caps.properties.apiVersion);
    state->enabled = EnabledFeatures::gather(context, state->caps);
    state->creation_feedback = state->caps.properties.apiVersion >= VK_API_VERSION_1_3 ||
                               state->enabled.has_extension(VK_EXT_PIPELINE_CREATION_FEEDBACK_EXTENSION_NAME);
    state->context.enabled_feature_chain = nullptr;  // read: the application may free it now
    state->context.enabled_extensions = nullptr;
    return Dearchiver(std::move(state));
  });
}

Result<void> Dearchiver::add_archive(Archive archive) {
  return api_guard("Dearchiver::add_archive", [&]() -> Result<void> {
    std::lock_guard lock(state_->mutex);
    // The lists grow together or not at all: room first, then nothing below throws.
    State& st = *state_;
    std::vector<State::Record> records(detail::ArchiveAccess::contents(archive).pipelines.size());
    st.records.reserve(st.records.size() + 1);
    st.archives.reserve(st.archives.size() + 1);
    st.lineage.reserve(st.lineage.size() + 1);
    st.active.reserve(st.active.size() + 1);
    st.records.push_back(std::move(records));
    st.lineage.push_back(st.active.size());
    st.active.push_back(st.archives.size());
    st.archives.push_back(std::move(archive));
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
  return state_->pipeline_names();
}

Result<const UnpackedPipeline*> Dearchiver::unpack_compute(std::string_view name,
                                                           const ModifyCallback& modify) {
  return api_guard("Dearchiver::unpack_compute", [&]() -> Result<const UnpackedPipeline*> {
    std::unique_lock lock(state_->mutex);
    return state_->unpack(lock, name, format::PipelineKind::compute, modify);
  });
}

Result<const UnpackedPipeline*> Dearchiver::unpack_graphics(std::string_view name,
                                                            const ModifyCallback& modify) {
  return api_guard("Dearchiver::unpack_graphics", [&]() -> Result<const UnpackedPipeline*> {
    std::unique_lock lock(state_->mutex);
    return state_->unpack(lock, name, format::PipelineKind::graphics, modify);
  });
}

namespace {

// The first archive that has an object of that name, as (archive, index).
template <class Find>
std::optional<std::pair<size_t, uint32_t>> find_named(const Dearchiver::State& state, Find&& find_in) {
  for (size_t i : state.active)
    if (auto index = find_in(state.contents(i))) return std::pair{i, *index};
  return std::nullopt;
}

}  // namespace

Result<const UnpackedSignature*> Dearchiver::unpack_signature(std::string_view name) {
  return api_guard("Dearchiver::unpack_signature", [&]() -> Result<const UnpackedSignature*> {
    std::lock_guard lock(state_->mutex);
    auto found = find_named(*state_, [&](const format::Contents& c) -> std::optional<uint32_t> {
      for (uint32_t i = 0; i < c.set_layouts.size(); ++i)
        if (!c.set_layouts[i].name.empty() && c.set_layouts[i].name == name) return i;
      return std::nullopt;
    });
    if (!found) {
      return detail::failure(ErrorCode::not_found,
                             "no resource signature named '" + std::string(name) + "'" +
                                 did_you_mean(name, state_->names_of({ObjectKind::resource_signature})));
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
    auto found = find_named(*state_, [&](const format::Contents& c) -> std::optional<uint32_t> {
      for (uint32_t i = 0; i < c.render_passes.size(); ++i)
        if (c.render_passes[i].name == name) return i;
      return std::nullopt;
    });
    if (!found) {
      return detail::failure(ErrorCode::not_found,
                             "no render pass named '" + std::string(name) + "'" +
                                 did_you_mean(name, state_->names_of({ObjectKind::render_pass})));
    }
    return state_->cache.render_pass(found->first, found->second);
  });
}

Result<UnpackedShader> Dearchiver::unpack_shader(std::string_view name) {
  return api_guard("Dearchiver::unpack_shader", [&]() -> Result<UnpackedShader> {
    std::lock_guard lock(state_->mutex);
    auto found = find_named(*state_, [&](const format::Contents& c) -> std::optional<uint32_t> {
      auto it = std::lower_bound(c.standalone_shaders.begin(), c.standalone_shaders.end(), name,
                                 [&](uint32_t s, std::string_view n) { return c.shaders[s].name < n; });
      if (it != c.standalone_shaders.end() && c.shaders[*it].name == name) return *it;
      return std::nullopt;
    });
    if (!found) {
      return detail::failure(ErrorCode::not_found,
                             "no standalone shader named '" + std::string(name) + "'" +
                                 did_you_mean(name, state_->names_of({ObjectKind::shader})));
    }
    const format::Shader& shader = state_->contents(found->first).shaders[found->second];
    auto module = state_->cache.module(found->first, shader.blob, shader.name);
    if (!module) return module.error();
    state_->cache.hand_out(*module);
    return UnpackedShader{shader.name, *module, static_cast<VkShaderStageFlagBits>(shader.stage),
                          shader.entry_point};
  });
}

}  // namespace statepack
