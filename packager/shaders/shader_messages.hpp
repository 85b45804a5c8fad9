// Compiler errors of many shaders, each distinct one reported once. Shaders share #include files: an
// error in one is the same file, line and message for every shader that includes it, and one error
// naming those shaders says more than a copy per shader.
#pragma once

#include <map>
#include <mutex>
#include <set>
#include <string>
#include <tuple>

#include "notation/diagnostics.hpp"

namespace statepack::packager {

class ShaderMessages {
 public:
  // Thread-safe: shaders compile in parallel.
  void error(const Location& where, const std::string& shader, const std::string& message);
  bool empty() const;
  // Adds one error per distinct (location, message), naming every shader that produced it.
  void report(Diagnostics& diag) const;

 private:
  using Key = std::tuple<std::string, int, int, std::string, std::string>;  // file, line, col, pointer, text
  mutable std::mutex mutex_;
  std::map<Key, std::set<std::string>> shaders_by_message_;  // ordered: the output does not depend on threads
};

}  // namespace statepack::packager
