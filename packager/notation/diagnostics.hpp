// Error collection for a packager run: every problem is kept (not only the first) and printed as
//   file:line:col: error: message [JSON pointer]
#pragma once

#include <iosfwd>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "support/printable.hpp"

namespace statepack::packager {

struct Location {
  std::string file;     // as the user named it (relative paths stay relative)
  int line = 0;         // 1-based; 0 when unknown
  int column = 0;       // 1-based; 0 when unknown
  std::string pointer;  // JSON pointer of the object involved, or empty
};

struct Diagnostic {
  enum class Severity { error, warning, note } severity = Severity::error;
  Location where;
  std::string message;
};

std::string format_diagnostic(const Diagnostic& d);
std::string location_text(const Location& where);  // file:line:col

// Names and paths from input, made safe for a terminal (support/printable.hpp).
using detail::printable;

// Collects diagnostics up to a limit of errors (0: no limit); past it, errors are counted but not kept,
// and `full()` tells readers to stop early instead of producing millions of them.
class Diagnostics {
 public:
  explicit Diagnostics(size_t max_errors = kDefaultMaxErrors) : max_errors_(max_errors) {}
  static constexpr size_t kDefaultMaxErrors = 100;
  void error(Location where, std::string message);
  void warning(Location where, std::string message);
  void note(Location where, std::string message);
  bool has_errors() const;
  bool full() const;                   // the error limit was reached
  size_t dropped_error_count() const;  // errors past the limit
  size_t error_count() const;
  std::vector<Diagnostic> all() const;
  void print(std::ostream& out) const;

 private:
  void add(Diagnostic::Severity severity, Location where, std::string message);

  mutable std::mutex mutex_;  // shaders compile on several threads
  std::vector<Diagnostic> items_;
  size_t max_errors_;
  size_t errors_ = 0, dropped_ = 0, dropped_others_ = 0;
};

}  // namespace statepack::packager
