// Error collection for a packager run: every problem is kept (not only the first) and printed as
//   file:line:col: error: message [JSON pointer]
#pragma once

#include <iosfwd>
#include <mutex>
#include <string>
#include <vector>

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

class Diagnostics {
 public:
  void error(Location where, std::string message);
  void warning(Location where, std::string message);
  void note(Location where, std::string message);
  bool has_errors() const;
  size_t error_count() const;
  std::vector<Diagnostic> all() const;
  void print(std::ostream& out) const;

 private:
  mutable std::mutex mutex_;  // shaders compile on several threads
  std::vector<Diagnostic> items_;
};

}  // namespace statepack::packager
