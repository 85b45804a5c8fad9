// Dearchiver::reload: a new build of an archive replaces the old one in a running application. Each
// pipeline unpacked from the old archive is compared with its namesake in the new one by content; a
// changed one is planned and created from the new archive and swapped into its UnpackedPipeline, the
// old VkPipeline retired until the application says the GPU is done with it.
//
// The replaced archive stays in `archives` (its index keeps its meaning) until nothing made from it is
// in use: a pipeline whose reload failed still comes from it, and is compared again at the next reload.
#include <algorithm>
#include <cstring>

#include "api_guard.hpp"

#include "archive_access.hpp"
#include "dearchiver_state.hpp"
#include "patchable_state.hpp"
#include "support/failure.hpp"
#include "support/printable.hpp"
#include "variant_key.hpp"
#include "vk_enum_names.hpp"

namespace statepack {
using namespace detail;

namespace {

bool same_blob(std::span<const uint32_t> a, std::span<const uint32_t> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

// Whether two bindings have the same immutable sampler, by value (or both none).
bool same_immutable_sampler(const format::Contents& ca, const format::Binding& x, const format::Contents& cb,
                            const format::Binding& y) {
  const bool fixed = x.immutable_sampler != format::kNone;
  if (fixed != (y.immutable_sampler != format::kNone)) return false;
  return !fixed || ca.samplers[x.immutable_sampler] == cb.samplers[y.immutable_sampler];
}

// A set layout as Vulkan and the application see it: its bindings, each with its immutable sampler's
// values rather than its place in the archive.
bool same_set_layout(const format::Contents& ca, uint32_t a, const format::Contents& cb, uint32_t b) {
  if (a == format::kNone || b == format::kNone) return a == b;
  const format::SetLayout& la = ca.set_layouts[a];
  const format::SetLayout& lb = cb.set_layouts[b];
  if (la.name != lb.name || la.binding_index != lb.binding_index || la.bindings.size() != lb.bindings.size())
    return false;
  for (size_t i = 0; i < la.bindings.size(); ++i) {
    if (!same_immutable_sampler(ca, la.bindings[i], cb, lb.bindings[i])) return false;
    format::Binding x = la.bindings[i], y = lb.bindings[i];
    x.immutable_sampler = y.immutable_sampler = 0;  // compared by value above
    if (!(x == y)) return false;
  }
  return true;
}

// Whether the pipeline would be created exactly as before: its record (without the indices into the
// archive's tables, which differ between builds) and what those indices lead to.
bool same_pipeline(const format::Contents& ca, const format::Pipeline& a, const format::Contents& cb,
                   const format::Pipeline& b) {
  if (a.shaders.size() != b.shaders.size() || a.set_layouts.size() != b.set_layouts.size()) return false;
  format::Pipeline x = a, y = b;
  x.shaders.clear(), y.shaders.clear();
  x.set_layouts.clear(), y.set_layouts.clear();
  x.render_pass = y.render_pass = 0;
  if (!(x == y)) return false;
  if ((a.render_pass == format::kNone) != (b.render_pass == format::kNone)) return false;
  if (a.render_pass != format::kNone && !(ca.render_passes[a.render_pass] == cb.render_passes[b.render_pass]))
    return false;
  for (size_t i = 0; i < a.set_layouts.size(); ++i)
    if (!same_set_layout(ca, a.set_layouts[i], cb, b.set_layouts[i])) return false;
  for (size_t i = 0; i < a.shaders.size(); ++i) {
    const format::Shader& sa = ca.shaders[a.shaders[i]];
    const format::Shader& sb = cb.shaders[b.shaders[i]];
    if (sa.stage != sb.stage || sa.entry_point != sb.entry_point ||
        !same_blob(ca.spirv[sa.blob], cb.spirv[sb.blob]))
      return false;
  }
  return true;
}

std::string binding_text(const format::Binding& b) {
  char stages[16];
  std::snprintf(stages, sizeof stages, "0x%X", b.stage_flags);
  return std::string(format::descriptor_type_name(b.descriptor_type)) + " '" + printable(b.name) + "'" +
         (b.count > 1 ? " [" + std::to_string(b.count) + "]" : "") + " (stages " + stages + ")";
}

// The first difference between two pipelines' resource layouts, in words; empty when Vulkan would see
// the same layout (names aside).
std::string layout_change(const format::Contents& ca, const format::Pipeline& a, const format::Contents& cb,
                          const format::Pipeline& b) {
  if (a.push_constant_size != b.push_constant_size || a.push_constant_stages != b.push_constant_stages)
    return "its push constants changed from " + std::to_string(a.push_constant_size) + " to " +
           std::to_string(b.push_constant_size) + " bytes (or their stages)";
  const size_t sets = std::max(a.set_layouts.size(), b.set_layouts.size());
  static const std::vector<format::Binding> kEmpty;
  for (size_t set = 0; set < sets; ++set) {
    auto bindings = [](const format::Contents& c, const format::Pipeline& p, size_t s) -> const auto& {
      return s < p.set_layouts.size() && p.set_layouts[s] != format::kNone
                 ? c.set_layouts[p.set_layouts[s]].bindings
                 : kEmpty;
    };
    const auto& old_list = bindings(ca, a, set);
    const auto& new_list = bindings(cb, b, set);
    const std::string where = "set " + std::to_string(set) + " binding ";
    for (size_t i = 0; i < std::max(old_list.size(), new_list.size()); ++i) {
      if (i >= new_list.size()) return where + std::to_string(old_list[i].binding) + " was removed";
      if (i >= old_list.size()) return where + std::to_string(new_list[i].binding) + " was added";
      const format::Binding& x = old_list[i];
      const format::Binding& y = new_list[i];
      if (x.binding != y.binding)
        return where + std::to_string(std::min(x.binding, y.binding)) + " was " +
               (x.binding < y.binding ? "removed" : "added");
      if (x.descriptor_type != y.descriptor_type || x.count != y.count || x.stage_flags != y.stage_flags)
        return where + std::to_string(x.binding) + " changed from " + binding_text(x) + " to " +
               binding_text(y);
      if (!same_immutable_sampler(ca, x, cb, y))
        return where + std::to_string(x.binding) + " changed its immutable sampler";
    }
  }
  return {};
}

// The first difference between the render targets a graphics pipeline was made for and those of its
// new build (formats, count, samples, render pass attachments and subpass), in words; empty when the
// application's attachments and framebuffers still fit.
std::string target_change(const format::Contents& ca, const format::Pipeline& a, const PatchableState& was,
                          const format::Contents& cb, const format::Pipeline& b, const PatchableState& now) {
  if (a.kind != format::PipelineKind::graphics) return {};
  if ((a.render_pass == format::kNone) != (b.render_pass == format::kNone) || a.subpass != b.subpass)
    return "its render pass or subpass changed";
  if (a.render_pass != format::kNone) {
    const auto& x = ca.render_passes[a.render_pass].attachments;
    const auto& y = cb.render_passes[b.render_pass].attachments;
    bool same = x.size() == y.size();
    for (size_t i = 0; same && i < x.size(); ++i)
      same = x[i].format == y[i].format && x[i].samples == y[i].samples;
    return same ? std::string() : "the attachments of its render pass changed (formats or samples)";
  }
  if (was.color_count != now.color_count)
    return "its number of color targets changed from " + std::to_string(was.color_count) + " to " +
           std::to_string(now.color_count);
  for (uint32_t i = 0; i < was.color_count && i < was.color_formats.size(); ++i)
    if (was.color_formats[i] != now.color_formats[i])
      return "color target " + std::to_string(i) + " changed from " + vk_name(was.color_formats[i]) + " to " +
             vk_name(now.color_formats[i]);
  if (was.depth_stencil_format != now.depth_stencil_format)
    return "its depth-stencil format changed from " + vk_name(was.depth_stencil_format) + " to " +
           vk_name(now.depth_stencil_format);
  if (was.samples != now.samples)
    return "its sample count changed from " + vk_name(was.samples) + " to " + vk_name(now.samples);
  return {};
}

const format::Pipeline* find_in(const format::Contents& c, const std::string& name,
                                format::PipelineKind kind) {
  const format::Pipeline* found = format::find_by_name(c.pipelines, name);
  return found && found->kind == kind ? found : nullptr;
}

ObjectInfo info_of(const format::Pipeline& p) {
  return {p.name, p.kind == format::PipelineKind::compute ? ObjectKind::compute_pipeline
                                                          : ObjectKind::graphics_pipeline};
}

}  // namespace

void Dearchiver::State::wait_for_jobs(std::unique_lock<std::mutex>& lock) {
  for (;;) {
    std::shared_ptr<UnpackJob::Shared> running;
    for (auto& weak : jobs)
      if (auto job = weak.lock(); job && !job_finished(*job)) {
        running = std::move(job);
        break;
      }
    if (!running) return;
    lock.unlock();  // its threads take the lock to keep what they made
    wait_for_job(*running);
    running.reset();
    lock.lock();  // and look again: another job may have started meanwhile
  }
}

namespace {

using State = Dearchiver::State;

// The pipeline's name now resolves in the new archive: an unpatched one is what its record gives.
void attach(State& st, State::Place& place, const UnpackedPipeline* pipeline, const ArchivedPipeline& now) {
  if (!place.record) return;
  State::Record& record = st.record_of(now);
  place.record->unmodified = nullptr;
  record.unmodified = pipeline;
  place.record = &record;
}

// The pipeline left the archive: it stays the application's (until released), made from nothing.
void detach(State& st, State::Place& place) {
  if (place.record) place.record->unmodified = nullptr;
  place.record = nullptr;
  if (place.variant != st.variants.end()) st.variants.erase(place.variant);
  place.variant = st.variants.end();
  if (place.recorded != SIZE_MAX) st.recorded[place.recorded].gone = true;
  place.source = {SIZE_MAX, nullptr};
}

// A new VkPipeline for a changed pipeline, from the new archive, patched as the old one was, swapped into
// its UnpackedPipeline; the old one retired. The error says why not (nothing changed then).
std::optional<Error> recreate(State& st, const UnpackedPipeline* pipeline, State::Place& place,
                              const ArchivedPipeline& now, const ReloadOptions& options,
                              uint64_t generation) {
  const format::Pipeline& old = *place.source.pipeline;
  const ObjectInfo info = info_of(old);
  const bool compute = old.kind == format::PipelineKind::compute;
  const bool patched = place.recorded != SIZE_MAX;
  std::optional<PipelineVariant> variant;
  std::optional<Error> refused;
  struct Refused {};
  ModifyCallback modify;
  if (patched) {
    variant = PipelineVariant{old.name, info.kind,
                              recorded_changes(old, st.recorded[place.recorded].settled, compute)};
    modify = [&](PatchableState& s) {
      if (auto applied = variant->apply(s); !applied) {
        refused = applied.error();
        throw Refused{};
      }
      if (options.patch) options.patch(info, s);
    };
  }
  auto plan = compute ? st.planner.plan_compute(now, modify) : st.planner.plan_graphics(now, modify);
  if (refused) return *refused;
  if (!plan) return plan.error();
  Plan& made = **plan;
  const std::string stays =
      ", so the old pipeline stays (release it and unpack it again to use the new build)";
  if (made.out.layout != pipeline->layout || made.out.set_layouts != pipeline->set_layouts ||
      made.out.bindings.size() != pipeline->bindings.size()) {
    std::string why =
        layout_change(st.contents(place.source.archive), old, st.contents(now.archive), *now.pipeline);
    if (why.empty()) why = "its resource layout changed";
    return detail::failure(
        ErrorCode::layout_changed,
        "pipeline '" + printable(old.name) + "': " + why +
            ", which descriptor sets and push constants made for the old layout would not fit" + stays);
  }
  const PatchableState was = patched ? st.recorded[place.recorded].settled : to_patchable(old);
  if (std::string why = target_change(st.contents(place.source.archive), old, was, st.contents(now.archive),
                                      *now.pipeline, made.state);
      !why.empty())
    return detail::failure(ErrorCode::layout_changed,
                           "pipeline '" + printable(old.name) + "': " + why +
                               ", which the application's attachments were made for" + stays);
  if (auto created = st.create(made); !created) return created.error();
  // What may throw (allocations) before the swap; the new pipeline is destroyed if it does.
  try {
    st.retired.reserve(st.retired.size() + 1);
    if (patched) {
      std::string key = variant_key(old.name, made);
      State::Recorded& entry = st.recorded[place.recorded];
      if (auto k = st.recorded_keys.find(entry.key);
          k != st.recorded_keys.end() && k->second == place.recorded)
        st.recorded_keys.erase(k);
      entry.key.clear();
      if (place.variant != st.variants.end()) {
        st.variants.erase(place.variant);
        place.variant = st.variants.end();
      }
      if (st.recorded_keys.emplace(key, place.recorded).second) entry.key = key;
      auto [at, inserted] = st.variants.emplace(std::move(key), pipeline);
      if (inserted) place.variant = at;  // else another variant settled the same: that one is found
    }
  } catch (...) {
    st.caps.vk.vkDestroyPipeline(st.context.device, made.out.pipeline, st.context.allocator);
    throw;
  }
  UnpackedPipeline& target = st.pipelines[place.slot];
  st.retired.push_back({target.pipeline, generation});
  target.pipeline = made.out.pipeline;
  target.creation = made.out.creation;
  // The same layout, so the same bindings in the same order: only the names may have changed, swapped in
  // place so that BindingInfo pointers the application holds stay valid (immutable samplers are the same).
  for (size_t i = 0; i < target.bindings.size(); ++i) target.bindings[i].name.swap(made.out.bindings[i].name);
  if (patched) {
    State::Recorded& entry = st.recorded[place.recorded];
    entry.source = now;
    entry.bind_point = made.out.bind_point;
    entry.settled = std::move(made.state);
  }
  attach(st, place, pipeline, now);
  place.source = now;
  return std::nullopt;
}

// A variant made and released before the reload follows its pipeline into the new archive (its recorded
// changes applied to the new state), or is gone with it.
void follow(State& st, State::Recorded& r, const format::Contents& next, size_t now) {
  const format::Pipeline& old = *r.source.pipeline;
  const format::Pipeline* found = find_in(next, old.name, old.kind);
  if (!found) {
    r.gone = true;
    return;
  }
  if (!same_pipeline(st.contents(r.source.archive), old, next, *found)) {
    const bool compute = old.kind == format::PipelineKind::compute;
    PatchableState settled = to_patchable(*found);
    const PipelineVariant variant{old.name, info_of(old).kind, recorded_changes(old, r.settled, compute)};
    if (!variant.apply(settled)) {
      r.gone = true;
      return;
    }
    r.settled = std::move(settled);
    // The key named the old settled state: an unpack of that state now is another variant.
    if (auto k = st.recorded_keys.find(r.key); k != st.recorded_keys.end() && &st.recorded[k->second] == &r)
      st.recorded_keys.erase(k);
    r.key.clear();
  }
  r.source = {now, found};
}

// Archives no longer named and with nothing made from them in use: their bytes and modules go.
void forget_unused_archives(State& st) {
  std::vector<char> used(st.archives.size(), 0);
  for (size_t a : st.active) used[a] = 1;
  for (const auto& [pipeline, place] : st.place_of)
    if (place.source.pipeline) used[place.source.archive] = 1;
  for (const auto& r : st.recorded)
    if (!r.gone) used[r.source.archive] = 1;
  for (size_t a = 0; a < st.archives.size(); ++a) {
    if (used[a] || ArchiveAccess::discarded(st.archives[a])) continue;
    st.cache.forget(a);
    std::vector<State::Record>().swap(st.records[a]);
    ArchiveAccess::discard(st.archives[a]);
  }
}

}  // namespace

Result<ReloadReport> Dearchiver::State::reload(Archive archive, const ReloadOptions& options) {
  if (options.archive >= active.size())
    return detail::failure(ErrorCode::invalid_argument, "Dearchiver::reload: ReloadOptions::archive is " +
                                                            std::to_string(options.archive) + ", but " +
                                                            std::to_string(active.size()) +
                                                            " archive(s) were added");
  const size_t old = active[options.archive];
  if (!options.allow_content_version_change && archive.content_version() != archives[old].content_version())
    return detail::failure(ErrorCode::content_version_mismatch,
                           "Dearchiver::reload: the new archive's content version is " +
                               std::to_string(archive.content_version()) + ", the one it replaces has " +
                               std::to_string(archives[old].content_version()) +
                               " (ReloadOptions::allow_content_version_change accepts it)");
  // Room first, as add_archive: the lists grow together.
  std::vector<Record> new_records(ArchiveAccess::contents(archive).pipelines.size());
  records.reserve(records.size() + 1);
  lineage.reserve(lineage.size() + 1);
  archives.reserve(archives.size() + 1);
  records.push_back(std::move(new_records));
  lineage.push_back(options.archive);
  archives.push_back(std::move(archive));
  const size_t now = archives.size() - 1;
  active[options.archive] = now;

  ReloadReport report;
  const format::Contents& before = contents(old);
  const format::Contents& next = contents(now);
  for (const auto& p : next.pipelines)
    if (!find_in(before, p.name, p.kind)) report.added.push_back(p.name);
  // The pipelines made from this archive (or from an older build, where a reload failed), in the order
  // they were made.
  std::vector<std::pair<size_t, const UnpackedPipeline*>> live;
  for (const auto& [pipeline, place] : place_of)
    if (place.source.pipeline && lineage[place.source.archive] == options.archive)
      live.emplace_back(place.slot, pipeline);
  std::sort(live.begin(), live.end());
  const uint64_t next_generation = generation + 1;
  std::vector<char> followed(recorded.size(), 0);
  for (const auto& [slot, pipeline] : live) {
    Place& place = place_of.at(pipeline);
    const format::Pipeline& was = *place.source.pipeline;
    if (place.recorded != SIZE_MAX) followed[place.recorded] = 1;
    const format::Pipeline* found = find_in(next, was.name, was.kind);
    if (!found) {
      report.removed.push_back(was.name);
      detach(*this, place);
      continue;
    }
    const ArchivedPipeline in_next{now, found};
    if (same_pipeline(contents(place.source.archive), was, next, *found)) {
      report.kept.push_back(was.name);
      if (place.recorded != SIZE_MAX) recorded[place.recorded].source = in_next;
      attach(*this, place, pipeline, in_next);
      place.source = in_next;
      continue;
    }
    const std::string name = was.name;  // `was` may be forgotten below
    if (auto error = recreate(*this, pipeline, place, in_next, options, next_generation)) {
      report.failures.push_back({info_of(was), std::move(*error)});
      attach(*this, place, pipeline, in_next);  // unpacked by name, it is still the old one
      continue;
    }
    report.recreated.push_back(name);
  }
  for (size_t i = 0; i < recorded.size(); ++i)
    if (!recorded[i].gone && !followed[i] && lineage[recorded[i].source.archive] == options.archive)
      follow(*this, recorded[i], next, now);
  if (!report.recreated.empty()) generation = next_generation;
  report.generation = generation;
  forget_unused_archives(*this);
  return report;
}

Result<ReloadReport> Dearchiver::reload(Archive archive, const ReloadOptions& options) {
  return api_guard("Dearchiver::reload", [&]() -> Result<ReloadReport> {
    std::unique_lock lock(state_->mutex);
    state_->wait_for_jobs(lock);
    return state_->reload(std::move(archive), options);
  });
}

uint64_t Dearchiver::reload_generation() const {
  std::lock_guard lock(state_->mutex);
  return state_->generation;
}

size_t Dearchiver::destroy_retired(uint64_t through_generation) {
  std::lock_guard lock(state_->mutex);
  size_t destroyed = 0;
  std::erase_if(state_->retired, [&](const State::Retired& r) {
    if (r.generation > through_generation) return false;
    state_->caps.vk.vkDestroyPipeline(state_->context.device, r.pipeline, state_->context.allocator);
    ++destroyed;
    return true;
  });
  return destroyed;
}

}  // namespace statepack
