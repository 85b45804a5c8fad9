// Where things are in a JSON text, found without trusting it: every scan here is iterative (no
// recursion whose depth the input sets) and linear in the text.
//
// nlohmann-json 3.11 reports positions only for syntax errors, so semantic errors ("unknown key") look
// their place up by JSON pointer here, on demand: only the few values that have errors are ever
// located, so a large file costs no index of every value.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace statepack::packager {

// Deeper nesting than this is refused before parsing: DRSN needs fewer than ten levels, and the
// readers that follow (merging defaults, copying values) recurse per level.
inline constexpr size_t kMaxJsonDepth = 128;

struct TextPosition {
  int line = 0;
  int column = 0;  // in UTF-8 code points
};

// Problems of a JSON text's shape that nlohmann accepts silently or cannot survive.
struct StructureProblem {
  enum class Kind { too_deep, duplicate_key } kind;
  size_t offset = 0;        // the bracket that is too deep, or the second key
  size_t first_offset = 0;  // the first key, for duplicates
  std::string key;
};

// Scans a JSON text for nesting deeper than kMaxJsonDepth (stops there) and for keys repeated within
// one object. Safe on any bytes; meaningful on text that parses.
std::vector<StructureProblem> check_json_structure(std::string_view text);

class JsonPositions {
 public:
  explicit JsonPositions(std::string_view text) : text_(text) {}  // `text` must outlive this
  // Position of the value at `pointer` ("#key" appended: of its key), or of the nearest ancestor.
  TextPosition find(std::string_view pointer) const;
  // Line and column of a byte offset.
  TextPosition position_at(size_t offset) const;

 private:
  size_t locate(std::string_view pointer) const;
  void remember(const std::string& pointer, size_t offset) const;

  size_t code_points_before(size_t offset) const;

  static constexpr size_t kBlockSize = 4096;
  static constexpr size_t kMaxRemembered = 100'000;  // entries of offsets_
  std::string_view text_;
  mutable std::vector<size_t> line_starts_;                  // built on first use
  mutable std::vector<size_t> code_points_before_block_;     // per kBlockSize bytes, built with line_starts_
  mutable size_t cursor_offset_ = 0, cursor_count_ = 0;      // the last code_points_before
  mutable std::unordered_map<std::string, size_t> offsets_;  // pointer -> offset, resolved before
  mutable std::unordered_map<std::string, std::pair<size_t, size_t>> array_cursor_;  // index, offset
};

}  // namespace statepack::packager
