#include "json_reader.hpp"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>

#include "support/suggest.hpp"
#include "vulkan_spelling.hpp"

namespace statepack::packager {

std::string describe_value(const Json& j) {
  if (j.is_object()) return "an object";
  if (j.is_array()) return "an array";
  if (j.is_string()) {
    const auto& s = j.get_ref<const std::string&>();
    return "the string \"" + (s.size() > 40 ? s.substr(0, 40) + "..." : s) + "\"";
  }
  return j.dump();  // a number, true, false or null: short
}

Location JsonReader::at(const std::string& pointer) const {
  TextPosition p = positions_.find(pointer);
  return {display_, p.line, p.column, pointer};
}

Location JsonReader::at_key(const std::string& pointer) const {
  TextPosition p = positions_.find(pointer + "#key");
  return {display_, p.line, p.column, pointer};
}

void JsonReader::error(const std::string& pointer, std::string message) {
  // Past the error limit the error is only counted: no need to locate it.
  diag_.error(diag_.full() ? Location{display_} : at(pointer), std::move(message));
}

void JsonReader::warning(const std::string& pointer, std::string message) {
  diag_.warning(diag_.full() ? Location{display_} : at(pointer), std::move(message));
}

namespace {
std::vector<std::string> key_names(std::span<const schema::Property> properties) {
  std::vector<std::string> names;
  for (const auto& p : properties) names.emplace_back(p.key);
  return names;
}
}  // namespace

void JsonReader::check_keys(const Json& object, const std::string& pointer,
                            std::span<const schema::Property> allowed, const char* what) {
  for (const auto& item : object.items()) {
    const std::string& key = item.key();
    if (std::any_of(allowed.begin(), allowed.end(), [&](const schema::Property& p) { return p.key == key; }))
      continue;
    if (diag_.full()) return;  // stop early: a file of a million unknown keys needs no million lines
    diag_.error(at_key(pointer + "/" + key), "unknown " + std::string(what) + " key '" + key + "'" +
                                                 detail::did_you_mean(key, key_names(allowed)));
  }
}

bool JsonReader::expect_object(const Json& j, const std::string& pointer, const char* what) {
  if (j.is_object()) return true;
  error(pointer, std::string(what) + " must be an object, but is " + j.type_name());
  return false;
}

bool JsonReader::expect_array(const Json& j, const std::string& pointer, const char* what) {
  if (j.is_array()) return true;
  error(pointer, std::string(what) + " must be an array, but is " + j.type_name());
  return false;
}

std::optional<std::string> JsonReader::string(const Json& object, const char* key,
                                              const std::string& pointer) {
  auto it = object.find(key);
  if (it == object.end()) return std::nullopt;
  if (!it->is_string()) {
    error(pointer + "/" + key, std::string("'") + key + "' must be a string, but is " + it->type_name());
    return std::nullopt;
  }
  return it->get<std::string>();
}

std::optional<uint32_t> JsonReader::enum_value(const Json& j, const std::string& pointer, EnumTable table,
                                               const char* enum_name) {
  if (!j.is_string()) {
    error(pointer, std::string(enum_name) + " must be a string, but is " + j.type_name());
    return std::nullopt;
  }
  const auto& s = j.get_ref<const std::string&>();
  for (const auto& [name, value] : table) {
    if (name != s) continue;
    if (value == kUnsupportedValue) {
      error(pointer, std::string(enum_name) + " '" + s + "' is not supported by the Vulkan backend");
      return std::nullopt;
    }
    return value;
  }
  std::vector<std::string> names;
  for (const auto& [name, value] : table)
    if (value != kUnsupportedValue) names.emplace_back(name);
  std::string hint;
  if (auto vulkan = notation_name_for_vulkan_spelling(table, s))
    hint = " (Vulkan's name; the notation's is '" + std::string(*vulkan) + "')";
  else
    hint = detail::did_you_mean(s, names);
  if (hint.empty()) {  // nothing close: say what is valid (the first 20; docs/notation.md has the rest)
    hint = " (valid: ";
    for (size_t i = 0; i < names.size() && i < 20; ++i) hint += (i ? ", " : "") + names[i];
    hint +=
        names.size() > 20 ? ", ... " + std::to_string(names.size() - 20) + " more in docs/notation.md)" : ")";
  }
  error(pointer, "unknown " + std::string(enum_name) + " '" + s + "'" + hint);
  return std::nullopt;
}

namespace {

// "VERTEX | PIXEL" as the array the notation takes, each part by its notation name where it is a
// Vulkan spelling ("VK_SHADER_STAGE_VERTEX_BIT").
std::string as_flag_array(const std::string& text, EnumTable table) {
  std::string out = "[";
  size_t start = 0;
  while (start <= text.size()) {
    size_t bar = std::min(text.find('|', start), text.size());
    std::string part = text.substr(start, bar - start);
    part.erase(0, part.find_first_not_of(" \t"));
    part.erase(part.find_last_not_of(" \t") + 1);
    if (auto name = notation_name_for_vulkan_spelling(table, part)) part = *name;
    out += (out.size() > 1 ? ", \"" : "\"") + part + "\"";
    start = bar + 1;
  }
  return out + "]";
}

}  // namespace

std::optional<uint32_t> JsonReader::flags_value(const Json& j, const std::string& pointer, EnumTable table,
                                                const char* enum_name) {
  // Diligent's reader takes one name or an array of names (DeserializeBitwiseEnum); "A | B" is an
  // unknown name there too. Accepting it would make files that only statepack reads, so it stays an
  // error, one that shows the spelling that works.
  if (j.is_string() && j.get_ref<const std::string&>().find('|') != std::string::npos) {
    const auto& s = j.get_ref<const std::string&>();
    error(pointer, std::string(enum_name) + " '" + s +
                       "': bit flags are combined as an array, not with '|' (as in Diligent's notation): " +
                       as_flag_array(s, table));
    return std::nullopt;
  }
  if (j.is_string()) return enum_value(j, pointer, table, enum_name);
  if (!j.is_array()) {
    error(pointer,
          std::string(enum_name) + " must be a string or an array of strings, but is " + j.type_name());
    return std::nullopt;
  }
  uint32_t bits = 0;
  bool ok = true;
  for (size_t i = 0; i < j.size(); ++i) {
    auto v = enum_value(j[i], pointer + "/" + std::to_string(i), table, enum_name);
    if (v) bits |= *v;
    ok = ok && v.has_value();
  }
  return ok ? std::optional<uint32_t>(bits) : std::nullopt;
}

void JsonReader::enum_field(const Json& object, const char* key, const std::string& pointer, EnumTable table,
                            const char* enum_name, uint32_t& out) {
  auto it = object.find(key);
  if (it == object.end()) return;
  if (auto v = enum_value(*it, pointer + "/" + key, table, enum_name)) out = *v;
}

void JsonReader::flags_field(const Json& object, const char* key, const std::string& pointer, EnumTable table,
                             const char* enum_name, uint32_t& out) {
  auto it = object.find(key);
  if (it == object.end()) return;
  if (auto v = flags_value(*it, pointer + "/" + key, table, enum_name)) out = *v;
}

void JsonReader::stage_flags_field(const Json& object, const char* key, const std::string& pointer,
                                   uint32_t& out) {
  uint32_t bits = 0;
  auto it = object.find(key);
  if (it == object.end()) return;
  if (auto v = flags_value(*it, pointer + "/" + key, kShaderStageFlags, "shader stage"))
    bits = *v;
  else
    return;
  out = bits & ~kUnproducibleStages;
  if (out != 0 || (bits & kUnproducibleStages) == 0) return;
  std::string names;
  for (const auto& [name, value] : kShaderStageFlags)
    if (std::has_single_bit(value) && (value & bits) && name != "LAST")
      names += std::string(names.empty() ? "" : ", ") + std::string(name);
  error(pointer + "/" + key, "'" + std::string(key) +
                                 "' names only stages that the Vulkan backend of statepack "
                                 "cannot produce (" +
                                 names + "): mesh, ray-tracing and tile shaders are not supported");
}

void JsonReader::boolean(const Json& object, const char* key, const std::string& pointer, uint32_t& out) {
  auto it = object.find(key);
  if (it == object.end()) return;
  if (!it->is_boolean())
    return error(pointer + "/" + key,
                 std::string("'") + key + "' must be true or false, but is " + it->type_name());
  out = it->get<bool>() ? 1 : 0;
}

void JsonReader::unsigned_number(const Json& object, const char* key, const std::string& pointer,
                                 uint32_t& out) {
  auto it = object.find(key);
  if (it == object.end()) return;
  // -0 is an integer zero in JSON (nlohmann stores it as a signed 0): accept it like 0.
  bool is_zero = it->is_number_integer() && it->get<int64_t>() == 0;
  if (!is_zero && (!it->is_number_unsigned() || it->get<uint64_t>() > 0xFFFFFFFFull))
    return error(
        pointer + "/" + key,
        std::string("'") + key + "' must be an integer from 0 to 4294967295, but is " + describe_value(*it));
  out = is_zero ? 0 : it->get<uint32_t>();
}

void JsonReader::signed_number(const Json& object, const char* key, const std::string& pointer,
                               int32_t& out) {
  auto it = object.find(key);
  if (it == object.end()) return;
  if (!it->is_number_integer() || it->get<int64_t>() < INT32_MIN || it->get<int64_t>() > INT32_MAX)
    return error(pointer + "/" + key,
                 std::string("'") + key + "' must be a 32-bit integer, but is " + describe_value(*it));
  out = it->get<int32_t>();
}

void JsonReader::float_number(const Json& object, const char* key, const std::string& pointer, float& out) {
  auto it = object.find(key);
  if (it == object.end()) return;
  if (!it->is_number())
    return error(pointer + "/" + key,
                 std::string("'") + key + "' must be a number, but is " + it->type_name());
  // A double beyond float's range would become infinity silently.
  double value = it->get<double>();
  if (!std::isfinite(value) || std::fabs(value) > double(FLT_MAX))
    return error(pointer + "/" + key, std::string("'") + key +
                                          "' must be a finite number within a 32-bit float's range, but is " +
                                          it->dump());
  out = static_cast<float>(value);
}

}  // namespace statepack::packager
