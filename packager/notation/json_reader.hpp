// Strict reading of one JSON document: every value read through here is type-checked, every
// object's keys are checked against the keys allowed there, and every problem becomes a diagnostic
// at file:line:col with the JSON pointer. Reading goes on after an error so a run reports them all.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "diagnostics.hpp"
#include "enum_tables.hpp"
#include "json_positions.hpp"
#include "notation_schema.hpp"

namespace statepack::packager {

using Json = nlohmann::json;

// A value for a message: scalars as written, strings cut short, containers by kind (never a dump of a
// whole subtree).
std::string describe_value(const Json& j);

class JsonReader {
 public:
  // `text` must outlive the reader (positions are looked up in it on demand).
  JsonReader(std::string display_name, std::string_view text, Diagnostics& diagnostics)
      : display_(std::move(display_name)), positions_(text), diag_(diagnostics) {}

  const std::string& file() const { return display_; }
  Location at(const std::string& pointer) const;
  Location at_key(const std::string& pointer) const;  // where the key itself is written
  void error(const std::string& pointer, std::string message);
  void warning(const std::string& pointer, std::string message);
  size_t error_count() const { return diag_.error_count(); }
  Diagnostics& diagnostics() { return diag_; }

  // Reports keys of `object` that are not in `allowed`, each with a suggestion.
  void check_keys(const Json& object, const std::string& pointer, std::span<const schema::Property> allowed,
                  const char* what);
  bool expect_object(const Json& j, const std::string& pointer, const char* what);
  bool expect_array(const Json& j, const std::string& pointer, const char* what);

  std::optional<std::string> string(const Json& object, const char* key, const std::string& pointer);
  std::optional<uint32_t> enum_value(const Json& j, const std::string& pointer, EnumTable table,
                                     const char* enum_name);
  // Bit-flag enums take one string or an array of strings, ORed together.
  std::optional<uint32_t> flags_value(const Json& j, const std::string& pointer, EnumTable table,
                                      const char* enum_name);

  // Optional fields: leave `out` alone when the key is absent or wrong.
  void enum_field(const Json& object, const char* key, const std::string& pointer, EnumTable table,
                  const char* enum_name, uint32_t& out);
  void flags_field(const Json& object, const char* key, const std::string& pointer, EnumTable table,
                   const char* enum_name, uint32_t& out);
  // A ShaderStages-like field: Vulkan stage bits in `out`. Stages statepack cannot produce (mesh, ray
  // tracing, tile) are dropped; naming only such stages is one error that says so.
  void stage_flags_field(const Json& object, const char* key, const std::string& pointer, uint32_t& out);
  void boolean(const Json& object, const char* key, const std::string& pointer, uint32_t& out);
  void unsigned_number(const Json& object, const char* key, const std::string& pointer, uint32_t& out);
  void signed_number(const Json& object, const char* key, const std::string& pointer, int32_t& out);
  void float_number(const Json& object, const char* key, const std::string& pointer, float& out);

 private:
  std::string display_;
  JsonPositions positions_;
  Diagnostics& diag_;
};

}  // namespace statepack::packager
