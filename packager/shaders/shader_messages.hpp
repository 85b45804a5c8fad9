// Compiler errors of many shaders, each distinct one reported once. Shaders share #include files: an
// error in one is the same file, line and message for every shader that includes it, and one error
// naming those shaders says more than a copy per shader.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <tuple>

#include "notation/diagnostics.hpp"

namespace statepack::packager {

// Appended to a shader's name by its OpenGL compile: messages then say "shader 'X' (OpenGL)", as every
// other OpenGL message of the packager does.
inline constexpr char kOpenGlCompile[] = " (OpenGL)";

class ShaderMessages {
 public:
  // Thread-safe: shaders compile in parallel.
  // `order`: the message's place in its compiler log. Messages at one place are reported in log order
  // (glslang names a cause before its consequences), whatever thread reported them first.
  void error(const Location& where, const std::string& shader, const std::string& message, size_t order = 0);
  bool empty() const;
  // Adds one error per distinct (location, message), naming every shader that produced it.
  void report(Diagnostics& diag) const;

 private:
  using Key = std::tuple<std::string, int, int, std::string, std::string>;  // file, line, col, pointer, text
  mutable std::mutex mutex_;
  struct Shaders {
    std::set<std::string> names;
    size_t order = SIZE_MAX;  // the least order it was reported with
  };
  std::map<Key, Shaders> shaders_by_message_;  // ordered: the output does not depend on threads
};

}  // namespace statepack::packager
