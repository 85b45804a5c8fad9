// Collects archive contents, storing each SPIR-V blob, shader, sampler and set layout once.
#pragma once

#include <algorithm>
#include <deque>
#include <map>
#include <span>
#include <vector>

#include "archive_format.hpp"

namespace statepack::packager {

class ContentsBuilder {
 public:
  // Deduplicates by content: XXH3 first, then a byte compare (a hash collision must not merge blobs).
  uint32_t add_blob(const std::vector<uint32_t>& words) {
    const auto* bytes = reinterpret_cast<const uint8_t*>(words.data());
    uint64_t hash = format::hash_bytes({bytes, words.size() * sizeof(uint32_t)});
    for (auto [it, end] = blob_by_hash_.equal_range(hash); it != end; ++it)
      if (std::ranges::equal(contents.spirv[it->second], words)) return it->second;
    blobs_.push_back(words);
    contents.spirv.emplace_back(blobs_.back());
    auto index = static_cast<uint32_t>(contents.spirv.size() - 1);
    blob_by_hash_.emplace(hash, index);
    return index;
  }
  uint32_t add_shader(const format::Shader& shader) {
    return add_unique(contents.shaders, shader, [](const format::Shader& a, const format::Shader& b) {
      return a.name == b.name && a.stage == b.stage && a.blob == b.blob && a.entry_point == b.entry_point;
    });
  }
  uint32_t add_sampler(const format::Sampler& sampler) {
    return add_unique(contents.samplers, sampler, std::equal_to<>());
  }
  uint32_t add_set_layout(const format::SetLayout& layout) {
    return add_unique(contents.set_layouts, layout, std::equal_to<>());
  }
  uint32_t add_render_pass(const format::RenderPass& pass) {
    return add_unique(contents.render_passes, pass, std::equal_to<>());
  }

  format::Contents contents;

 private:
  template <class T, class Equal>
  static uint32_t add_unique(std::vector<T>& list, const T& item, Equal&& equal) {
    for (uint32_t i = 0; i < list.size(); ++i)
      if (equal(list[i], item)) return i;
    list.push_back(item);
    return static_cast<uint32_t>(list.size() - 1);
  }

  std::deque<std::vector<uint32_t>> blobs_;  // stable storage behind contents.spirv
  std::multimap<uint64_t, uint32_t> blob_by_hash_;
};

}  // namespace statepack::packager
