#include "hlsl_combined_image_samplers.hpp"

#include <cctype>
#include <set>

#include "glslang_tree.hpp"

namespace statepack::packager {
namespace {

bool word_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// Where `line` (1-based) of `text` begins, or npos.
size_t line_start(const std::string& text, int line) {
  size_t at = 0;
  for (int i = 1; i < line; ++i) {
    at = text.find('\n', at);
    if (at == std::string::npos) return at;
    ++at;
  }
  return at;
}

}  // namespace

std::vector<std::string> combined_image_sampler_variables(
    const glslang::TShader& shader, const std::vector<AttributeSite>& sites,
    const std::function<const std::string*(const std::string& file)>& text_of) {
  std::set<std::string, std::less<>> candidates;  // the global textures and samplers
  for_each_global(shader, [&](const glslang::TIntermSymbol& symbol) {
    const glslang::TType& type = symbol.getType();
    if (type.getBasicType() != glslang::EbtSampler) return;
    const glslang::TSampler& sampler = type.getSampler();
    if (sampler.isPureSampler() || sampler.isTexture()) candidates.insert(symbol.getName().c_str());
  });
  std::vector<std::string> names;
  for (const AttributeSite& site : sites) {
    const std::string* text = text_of(site.file);
    if (!text) continue;
    size_t at = line_start(*text, site.line);
    if (at == std::string::npos) continue;
    at = text->find("combinedImageSampler", at);
    if (at == std::string::npos) continue;
    // The first word after the attribute that names a texture or sampler is what it was written on.
    for (at += 20; at < text->size();) {
      if ((*text)[at] == ';') break;  // the declaration ended without one: nothing to pair
      if (!word_char((*text)[at])) {
        ++at;
        continue;
      }
      size_t end = at;
      while (end < text->size() && word_char((*text)[end])) ++end;
      if (auto it = candidates.find(std::string_view(*text).substr(at, end - at)); it != candidates.end()) {
        names.push_back(*it);
        break;
      }
      at = end;
    }
  }
  return names;
}

}  // namespace statepack::packager
