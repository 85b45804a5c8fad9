#include "json_positions.hpp"

#include <cctype>

namespace statepack::packager {
namespace {

class Scanner {
 public:
  Scanner(std::string_view text, std::map<std::string, TextPosition, std::less<>>& out)
      : text_(text), out_(out) {}

  void value(const std::string& pointer) {
    skip_space();
    out_.emplace(pointer, position());
    if (at_end()) return;
    char c = text_[i_];
    if (c == '{') {
      advance();
      for (;;) {
        skip_space();
        if (at_end() || text_[i_] == '}') break;
        if (text_[i_] == ',') {
          advance();
          continue;
        }
        TextPosition key_position = position();
        std::string key = string();
        skip_space();
        if (!at_end() && text_[i_] == ':') advance();
        std::string child = pointer + "/" + escape(key);
        out_.emplace(child + "#key", key_position);
        value(child);
      }
      advance();
    } else if (c == '[') {
      advance();
      for (size_t index = 0;; ++index) {
        skip_space();
        if (at_end() || text_[i_] == ']') break;
        if (text_[i_] == ',') advance(), skip_space();
        value(pointer + "/" + std::to_string(index));
        skip_space();
        if (!at_end() && text_[i_] == ',')
          advance();
        else
          break;
      }
      skip_space();
      advance();
    } else if (c == '"') {
      string();
    } else {
      while (!at_end() && !std::isspace(static_cast<unsigned char>(text_[i_])) && text_[i_] != ',' &&
             text_[i_] != '}' && text_[i_] != ']')
        advance();
    }
  }

 private:
  bool at_end() const { return i_ >= text_.size(); }
  TextPosition position() const { return {line_, column_}; }
  void advance() {
    if (at_end()) return;
    if (text_[i_] == '\n')
      ++line_, column_ = 1;
    else if ((static_cast<unsigned char>(text_[i_]) & 0xC0) != 0x80)
      ++column_;  // count UTF-8 code points
    ++i_;
  }
  void skip_space() {
    while (!at_end() && std::isspace(static_cast<unsigned char>(text_[i_]))) advance();
  }
  std::string string() {
    std::string s;
    advance();  // opening quote
    while (!at_end() && text_[i_] != '"') {
      if (text_[i_] == '\\') {
        advance();
        if (at_end()) break;
        char e = text_[i_];
        s += e == 'n' ? '\n' : e == 't' ? '\t' : e == 'r' ? '\r' : e == 'b' ? '\b' : e == 'f' ? '\f' : e;
      } else {
        s += text_[i_];
      }
      advance();
    }
    advance();  // closing quote
    return s;
  }
  static std::string escape(const std::string& key) {
    std::string out;
    for (char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
    return out;
  }

  std::string_view text_;
  std::map<std::string, TextPosition, std::less<>>& out_;
  size_t i_ = 0;
  int line_ = 1, column_ = 1;
};

}  // namespace

JsonPositions::JsonPositions(std::string_view text) {
  Scanner(text, positions_).value("");
}

TextPosition JsonPositions::find(std::string_view pointer) const {
  std::string p(pointer);
  for (;;) {
    if (auto it = positions_.find(p); it != positions_.end()) return it->second;
    auto slash = p.rfind('/');
    if (slash == std::string::npos) return {};
    p.resize(slash);
  }
}

}  // namespace statepack::packager
