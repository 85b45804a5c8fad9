// Collects archive contents, storing each SPIR-V blob, shader, sampler and set layout once.
#pragma once

#include <algorithm>
#include <deque>
#include <map>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "format/archive_format.hpp"

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
  uint32_t add_shader(const format::Shader& shader) { return add_unique(contents.shaders, shader, shaders_); }
  uint32_t add_sampler(const format::Sampler& sampler) {
    return add_unique(contents.samplers, sampler, samplers_);
  }
  uint32_t add_set_layout(const format::SetLayout& layout) {
    return add_unique(contents.set_layouts, layout, set_layouts_);
  }
  uint32_t add_render_pass(const format::RenderPass& pass) {
    return add_unique(contents.render_passes, pass, render_passes_);
  }

  format::Contents contents;

 private:
  // Looked up by the record's bytes, so storing n records costs O(n), not O(n^2) comparisons (a merge
  // or a notation of thousands of signatures stays linear).
  using Index = std::unordered_map<std::string, uint32_t>;
  template <class T>
  static uint32_t add_unique(std::vector<T>& list, const T& item, Index& index) {
    auto [it, inserted] = index.try_emplace(format::record_key(item), static_cast<uint32_t>(list.size()));
    if (inserted) list.push_back(item);
    return it->second;
  }
  Index shaders_, samplers_, set_layouts_, render_passes_;

  std::deque<std::vector<uint32_t>> blobs_;  // stable storage behind contents.spirv
  std::multimap<uint64_t, uint32_t> blob_by_hash_;
};

}  // namespace statepack::packager
