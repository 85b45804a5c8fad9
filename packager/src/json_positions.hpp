// Line and column of every value in a JSON text, keyed by JSON pointer.
// nlohmann-json 3.11 reports positions only for syntax errors, so semantic errors ("unknown key")
// look their place up here. Runs only on text nlohmann already accepted.
#pragma once

#include <map>
#include <string>
#include <string_view>

namespace statepack::packager {

struct TextPosition {
  int line = 0;
  int column = 0;
};

class JsonPositions {
 public:
  explicit JsonPositions(std::string_view text);
  // Position of the value at `pointer`, or of the nearest ancestor that has one.
  TextPosition find(std::string_view pointer) const;

 private:
  std::map<std::string, TextPosition, std::less<>> positions_;
};

}  // namespace statepack::packager
