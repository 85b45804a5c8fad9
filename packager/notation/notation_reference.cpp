#include "notation_reference.hpp"

#include "enum_tables.hpp"

namespace statepack::packager {

std::vector<EnumReference> enum_reference() {
  std::vector<EnumReference> out;
  for (const EnumTableInfo& info : kEnumTableInfo) {
    EnumReference e;
    e.name = info.name;
    e.bit_flags = info.bit_flags;
    for (std::string_view keys = info.keys; !keys.empty();) {
      size_t comma = keys.find(", ");
      e.keys.push_back(keys.substr(0, comma));
      keys = comma == std::string_view::npos ? std::string_view() : keys.substr(comma + 2);
    }
    for (const auto& [name, value] : info.values)
      (value == kUnsupportedValue ? e.refused : e.accepted).push_back(name);
    out.push_back(std::move(e));
  }
  return out;
}

namespace {

std::string code_list(const std::vector<std::string_view>& names) {
  std::string text;
  for (size_t i = 0; i < names.size(); ++i) text += (i ? ", `" : "`") + std::string(names[i]) + "`";
  return text;
}

}  // namespace

std::string enum_reference_markdown(const std::vector<EnumReference>& enums) {
  std::string md =
      "<!-- Generated from packager/notation/enum_tables.hpp by statepack_docs; do not edit by hand. After "
      "changing a table: cmake --build build --target update_notation_docs -->\n";
  for (const EnumReference& e : enums) {
    md += "\n### " + std::string(e.name) + "\n\n";
    md += "Keys: " + code_list(e.keys) + ". ";
    md += e.bit_flags
              ? "Bit flags: one name or an array of names, combined (`[\"A\", \"B\"]`; `\"A | B\"` is an "
                "error).\n\n"
              : "One name.\n\n";
    md += "Values: " + code_list(e.accepted) + ".\n";
    if (!e.refused.empty())
      md += "\nKnown but refused (\"not supported by the Vulkan backend\"): " + code_list(e.refused) + ".\n";
  }
  return md;
}

std::optional<std::string> with_generated_section(const std::string& document, const std::string& content) {
  size_t begin = document.find(kGeneratedBegin);
  if (begin == std::string::npos) return std::nullopt;
  size_t body = document.find('\n', begin);
  size_t end = document.find(kGeneratedEnd, begin);
  if (body == std::string::npos || end == std::string::npos || end < body) return std::nullopt;
  return document.substr(0, body + 1) + content + document.substr(end);
}

}  // namespace statepack::packager
