// The Vulkan objects pipelines share, created once per archived object and kept until the Dearchiver
// goes: shader modules, descriptor set layouts (and the empty one that fills holes in the set numbering),
// immutable samplers, render passes and pipeline layouts. Every object is checked against the device
// before it is created. Not thread-safe: the Dearchiver's lock covers it.
//
// Set layouts, samplers and render passes are kept by content, not by archive: an archive that replaces
// another (Dearchiver::reload) gets the very handles its predecessor had for what did not change, so the
// application's descriptor sets and framebuffers, and the pipeline layouts made of them, stay good.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "device_limits.hpp"
#include "enabled_features.hpp"
#include "format/archive_format.hpp"
#include "format/spirv_walk.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::detail {

class ObjectCache {
 public:
  // `archives` is the Dearchiver's list: objects are keyed by (archive index, record index).
  ObjectCache(const DeviceContext& context, const DeviceCaps& caps, const EnabledFeatures& enabled,
              const std::vector<Archive>& archives)
      : context_(context), caps_(caps), enabled_(enabled), archives_(archives) {}
  ObjectCache(const ObjectCache&) = delete;
  ObjectCache& operator=(const ObjectCache&) = delete;
  ~ObjectCache();

  const format::Contents& contents(size_t archive) const;

  // `owner` names what needs the object, for errors.
  Result<VkShaderModule> module(size_t archive, uint32_t blob, std::string_view owner);
  // format::kNone gives the empty layout.
  Result<VkDescriptorSetLayout> set_layout(size_t archive, uint32_t index, std::string_view pipeline);
  Result<VkSampler> sampler(size_t archive, uint32_t index, std::string_view binding);
  Result<VkRenderPass> render_pass(size_t archive, uint32_t index);
  Result<VkPipelineLayout> pipeline_layout(const std::vector<VkDescriptorSetLayout>& set_layouts,
                                           uint32_t push_constant_size, uint32_t push_constant_stages,
                                           std::string_view pipeline);

  // The sampler object set_layout created for a binding's immutable sampler, or null.
  VkSampler immutable_sampler_of(size_t archive, const format::Binding& binding) const;
  // A blob's declarations, as the archive's load walked them (every blob a shader uses).
  const spirv::Module* walked(size_t archive, uint32_t blob);

  // A module the application was given (a standalone shader): never destroyed before the cache.
  void hand_out(VkShaderModule module) { handed_out_.insert(module); }
  // The archive is gone (replaced by a reload, nothing made from it in use): its shader modules are
  // destroyed unless handed out (pipelines do not need them once created), and its index is forgotten.
  // Objects kept by content stay, for whoever uses them.
  void forget(size_t archive);

 private:
  // What a lookup that finds nothing makes.
  Result<VkDescriptorSetLayout> create_set_layout(size_t archive, uint32_t index, std::string_view pipeline);
  Result<VkSampler> create_sampler(size_t archive, uint32_t index, std::string_view binding);
  Result<VkRenderPass> create_render_pass(size_t archive, uint32_t index);
  using Key = std::pair<size_t, uint32_t>;  // (archive, index of the record or blob)
  // The one place a cached object is looked up, or created and kept.
  template <class Handle, class Create>
  Result<Handle> find_or_create(std::map<Key, Handle>& cache, Key key, Create&& create);
  // The same for an object kept by content: `by_index` remembers where each archive's record led,
  // `by_content` owns the handles.
  template <class Handle, class Create>
  Result<Handle> find_or_create(std::map<Key, Handle>& by_index, std::map<std::string, Handle>& by_content,
                                Key key, const std::string& content, Create&& create);
  std::string set_layout_content(size_t archive, const format::SetLayout& layout) const;

  const DeviceContext& context_;
  const DeviceCaps& caps_;
  const EnabledFeatures& enabled_;  // features, and SPIR-V capabilities, are checked against it
  const std::vector<Archive>& archives_;
  std::map<Key, VkShaderModule> modules_;
  std::set<VkShaderModule> handed_out_;  // kept when their archive is forgotten
  std::map<Key, VkDescriptorSetLayout> set_layouts_;
  std::map<std::string, VkDescriptorSetLayout> set_layouts_by_content_;
  std::map<Key, VkSampler> samplers_;
  std::map<std::string, VkSampler> samplers_by_content_;
  std::map<Key, VkRenderPass> render_passes_;
  std::map<std::string, VkRenderPass> render_passes_by_content_;
  VkDescriptorSetLayout empty_set_layout_ = VK_NULL_HANDLE;
  std::map<std::tuple<std::vector<VkDescriptorSetLayout>, uint32_t, uint32_t>, VkPipelineLayout, std::less<>>
      pipeline_layouts_;  // (set layouts, push size, push stages)
};

}  // namespace statepack::detail
