// One JSON document parsed strictly: nesting deeper than kMaxJsonDepth is refused before parsing, a
// number out of a double's range is an error (nlohmann would throw), and a key repeated in one object
// is an error naming both places (nlohmann would keep the last silently).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace statepack::packager {

struct JsonProblem {
  size_t offset = 0;  // byte offset in the text
  std::string message;
};

struct JsonDocument {
  nlohmann::json root;              // discarded when parsing failed
  std::vector<JsonProblem> errors;  // empty when the document is fine
  bool parsed = false;              // root holds the document (even with duplicate-key errors)
};

// `text` without a byte-order mark (see strip_utf8_bom).
JsonDocument parse_json_document(std::string_view text);

// Drops a leading UTF-8 byte-order mark, so positions count from the first character after it.
std::string_view strip_utf8_bom(std::string_view text);

}  // namespace statepack::packager
