#include "json_positions.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

namespace statepack::packager {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

size_t skip_space(std::string_view t, size_t i) {
  while (i < t.size() && is_space(t[i])) ++i;
  return i;
}

void append_utf8(std::string& out, uint32_t cp) {
  if (cp < 0x80) {
    out += char(cp);
  } else if (cp < 0x800) {
    out += char(0xC0 | cp >> 6), out += char(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += char(0xE0 | cp >> 12), out += char(0x80 | (cp >> 6 & 0x3F)), out += char(0x80 | (cp & 0x3F));
  } else {
    out += char(0xF0 | cp >> 18), out += char(0x80 | (cp >> 12 & 0x3F));
    out += char(0x80 | (cp >> 6 & 0x3F)), out += char(0x80 | (cp & 0x3F));
  }
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// Reads the string starting at t[i] == '"', decoding escapes as JSON does (so "\u0050ipelines" is
// "Pipelines"); returns the offset after the closing quote.
size_t read_string(std::string_view t, size_t i, std::string* out) {
  ++i;
  auto hex4 = [&](size_t at) -> int32_t {
    if (at + 4 > t.size()) return -1;
    int32_t v = 0;
    for (size_t k = 0; k < 4; ++k) {
      int d = hex_digit(t[at + k]);
      if (d < 0) return -1;
      v = v * 16 + d;
    }
    return v;
  };
  while (i < t.size() && t[i] != '"') {
    if (t[i] != '\\') {
      if (out) *out += t[i];
      ++i;
      continue;
    }
    if (++i >= t.size()) break;
    char e = t[i++];
    if (e != 'u') {
      if (out)
        *out += e == 'n' ? '\n' : e == 't' ? '\t' : e == 'r' ? '\r' : e == 'b' ? '\b' : e == 'f' ? '\f' : e;
      continue;
    }
    int32_t cp = hex4(i);
    if (cp < 0) continue;
    i += 4;
    if (cp >= 0xD800 && cp <= 0xDBFF && i + 1 < t.size() && t[i] == '\\' && t[i + 1] == 'u') {
      int32_t low = hex4(i + 2);
      if (low >= 0xDC00 && low <= 0xDFFF) {
        cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
        i += 6;
      }
    }
    if (out) append_utf8(*out, uint32_t(cp));
  }
  return std::min(i + 1, t.size());
}

// Skips one value (any depth, iteratively); returns the offset after it.
size_t skip_value(std::string_view t, size_t i) {
  i = skip_space(t, i);
  if (i >= t.size()) return i;
  if (t[i] == '"') return read_string(t, i, nullptr);
  if (t[i] != '{' && t[i] != '[') {
    while (i < t.size() && !is_space(t[i]) && t[i] != ',' && t[i] != '}' && t[i] != ']') ++i;
    return i;
  }
  size_t depth = 0;
  while (i < t.size()) {
    char c = t[i];
    if (c == '"') {
      i = read_string(t, i, nullptr);
      continue;
    }
    if (c == '{' || c == '[') ++depth;
    if ((c == '}' || c == ']') && --depth == 0) return i + 1;
    ++i;
  }
  return i;
}

std::string unescape_segment(std::string_view s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '~' && i + 1 < s.size() && (s[i + 1] == '0' || s[i + 1] == '1')) {
      out += s[i + 1] == '0' ? '~' : '/';
      ++i;
    } else {
      out += s[i];
    }
  }
  return out;
}

}  // namespace

std::vector<StructureProblem> check_json_structure(std::string_view t) {
  constexpr size_t kMaxReportedDuplicates = 1000;  // more would only be cut by the error limit
  std::vector<StructureProblem> problems;
  struct Frame {
    bool object;
    std::unordered_map<std::string, size_t> keys;  // key -> offset of its first occurrence
    bool expect_key = true;                        // objects: the next string is a key
  };
  std::vector<Frame> stack;
  size_t i = 0;
  while (i < t.size()) {
    char c = t[i];
    if (c == '"') {
      if (!stack.empty() && stack.back().object && stack.back().expect_key) {
        std::string key;
        size_t key_offset = i;
        i = read_string(t, i, &key);
        stack.back().expect_key = false;
        auto [it, inserted] = stack.back().keys.try_emplace(std::move(key), key_offset);
        if (!inserted && problems.size() < kMaxReportedDuplicates)
          problems.push_back({StructureProblem::Kind::duplicate_key, key_offset, it->second, it->first});
      } else {
        i = read_string(t, i, nullptr);
      }
      continue;
    }
    if (c == '{' || c == '[') {
      if (stack.size() >= kMaxJsonDepth) {
        problems.push_back({StructureProblem::Kind::too_deep, i, 0, {}});
        return problems;
      }
      stack.push_back({c == '{', {}, true});
    } else if ((c == '}' || c == ']') && !stack.empty()) {
      stack.pop_back();
    } else if (c == ',' && !stack.empty() && stack.back().object) {
      stack.back().expect_key = true;
    }
    ++i;
  }
  return problems;
}

// Code points in text_[0, offset): counted from the nearest block boundary, so that any position costs
// at most one block's scan however long its line is (minified JSON is one line).
size_t JsonPositions::code_points_before(size_t offset) const {
  const size_t block = offset / kBlockSize;
  size_t from = block * kBlockSize, count = code_points_before_block_[block];
  // Positions are mostly asked for in text order: go on from the last one when it is closer.
  if (cursor_offset_ <= offset && cursor_offset_ > from) from = cursor_offset_, count = cursor_count_;
  for (size_t i = from; i < offset; ++i) count += (static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80;
  if (offset > cursor_offset_) cursor_offset_ = offset, cursor_count_ = count;  // (a line start goes back)
  return count;
}

TextPosition JsonPositions::position_at(size_t offset) const {
  if (line_starts_.empty()) {
    line_starts_.push_back(0);
    code_points_before_block_.push_back(0);
    size_t code_points = 0;
    for (size_t i = 0; i < text_.size(); ++i) {
      if (text_[i] == '\n') line_starts_.push_back(i + 1);
      code_points += (static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80;
      if ((i + 1) % kBlockSize == 0) code_points_before_block_.push_back(code_points);
    }
  }
  offset = std::min(offset, text_.size());
  auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset) - 1;
  // A short line is scanned from its start (the usual case: a few dozen bytes); a long one (minified
  // JSON) through the block counts, so either way a position costs at most one block's scan.
  size_t column = 1;
  if (offset - *it <= kBlockSize) {
    for (size_t i = *it; i < offset; ++i) column += (static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80;
  } else {
    column = code_points_before(offset) - code_points_before(*it) + 1;
  }
  return {int(it - line_starts_.begin()) + 1, int(std::min<size_t>(column, INT32_MAX))};
}

TextPosition JsonPositions::find(std::string_view pointer) const {
  return position_at(locate(pointer));
}

size_t JsonPositions::locate(std::string_view pointer) const {
  bool want_key = false;
  if (pointer.size() >= 4 && pointer.substr(pointer.size() - 4) == "#key") {
    want_key = true;
    pointer.remove_suffix(4);
  }
  if (auto it = offsets_.find(std::string(pointer) + (want_key ? "#key" : "")); it != offsets_.end())
    return it->second;
  // Walk down segment by segment from the root, reusing what earlier lookups found.
  size_t at = skip_space(text_, 0);
  size_t key_at = at;
  std::string prefix;
  size_t start = 0;
  while (start < pointer.size()) {
    size_t end = pointer.find('/', start + 1);
    if (end == std::string_view::npos) end = pointer.size();
    std::string segment = unescape_segment(pointer.substr(start + 1, end - start - 1));
    std::string child = prefix + std::string(pointer.substr(start, end - start));
    if (auto it = offsets_.find(child); it != offsets_.end() && !(want_key && end == pointer.size())) {
      at = it->second, prefix = std::move(child), start = end;
      continue;
    }
    if (at >= text_.size()) return at;
    bool found = false;
    if (text_[at] == '{') {
      size_t i = at + 1;
      while (!found) {
        i = skip_space(text_, i);
        if (i >= text_.size() || text_[i] == '}') break;
        if (text_[i] == ',') {
          ++i;
          continue;
        }
        if (text_[i] != '"') break;
        std::string key;
        size_t this_key = i;
        i = skip_space(text_, read_string(text_, i, &key));
        if (i < text_.size() && text_[i] == ':') ++i;
        i = skip_space(text_, i);
        if (key == segment) {
          key_at = this_key, at = i, found = true;
        } else {
          i = skip_value(text_, i);
        }
      }
    } else if (text_[at] == '[') {
      size_t index = 0;
      bool numeric = !segment.empty() && segment.size() < 19 &&
                     std::all_of(segment.begin(), segment.end(), [](char d) { return d >= '0' && d <= '9'; });
      if (numeric) index = std::stoull(segment);
      // Errors come in element order, so resume from the last element located in this array.
      size_t current = 0, i = skip_space(text_, at + 1);
      if (auto cursor = array_cursor_.find(prefix);
          cursor != array_cursor_.end() && cursor->second.first <= index)
        current = cursor->second.first, i = cursor->second.second;
      while (numeric && !found) {
        i = skip_space(text_, i);
        if (i >= text_.size() || text_[i] == ']') break;
        if (current == index) {
          at = key_at = i, found = true;
          array_cursor_[prefix] = {current, i};
          break;
        }
        i = skip_space(text_, skip_value(text_, i));
        if (i < text_.size() && text_[i] == ',') ++i;
        ++current;
      }
    }
    if (!found) return at;  // the nearest ancestor
    remember(child, at);
    prefix = std::move(child);
    start = end;
  }
  size_t result = want_key ? key_at : at;
  remember(std::string(pointer) + (want_key ? "#key" : ""), result);
  return result;
}

void JsonPositions::remember(const std::string& pointer, size_t offset) const {
  // Bounded memory: a full cache starts over rather than refusing new entries, so the objects looked up
  // now ("/Pipelines" after 200,000 shaders) are found again without rescanning the text before them.
  if (offsets_.size() >= kMaxRemembered) offsets_.clear();
  offsets_[pointer] = offset;
}

}  // namespace statepack::packager
