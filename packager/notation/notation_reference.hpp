// The notation's enum values as the reader accepts them, walked once from enum_tables.hpp's registry
// into a plain model that each output renders: Markdown for docs/notation.md now, a JSON Schema
// (issue 12) later from the same model, so neither can drift from the reader.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace statepack::packager {

struct EnumReference {
  std::string_view name;               // Diligent's enum type
  std::vector<std::string_view> keys;  // the notation keys that take it
  bool bit_flags = false;              // one name or an array of names
  std::vector<std::string_view> accepted;
  std::vector<std::string_view> refused;  // Diligent's names the Vulkan backend cannot express
};

std::vector<EnumReference> enum_reference();

// The Markdown that docs/notation.md holds between the markers below.
std::string enum_reference_markdown(const std::vector<EnumReference>& enums);

inline constexpr std::string_view kGeneratedBegin = "<!-- BEGIN statepack_docs enums -->";
inline constexpr std::string_view kGeneratedEnd = "<!-- END statepack_docs enums -->";

// `document` with the text between the markers replaced by `content`; nullopt when the markers are
// missing or out of order.
std::optional<std::string> with_generated_section(const std::string& document, const std::string& content);

}  // namespace statepack::packager
