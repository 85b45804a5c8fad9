#include "diagnostics.hpp"

#include <algorithm>
#include <ostream>
#include <tuple>

namespace statepack::packager {

std::string location_text(const Location& where) {
  std::string text = where.file.empty() ? "statepack" : where.file;
  if (where.line > 0) {
    text += ":" + std::to_string(where.line);
    if (where.column > 0) text += ":" + std::to_string(where.column);
  }
  return text;
}

std::string format_diagnostic(const Diagnostic& d) {
  std::string text = location_text(d.where);
  text += d.severity == Diagnostic::Severity::error     ? ": error: "
          : d.severity == Diagnostic::Severity::warning ? ": warning: "
                                                        : ": note: ";
  text += d.message;
  if (!d.where.pointer.empty()) text += " [" + d.where.pointer + "]";
  return text;
}

void Diagnostics::error(Location where, std::string message) {
  std::lock_guard lock(mutex_);
  items_.push_back({Diagnostic::Severity::error, std::move(where), std::move(message)});
}

void Diagnostics::warning(Location where, std::string message) {
  std::lock_guard lock(mutex_);
  items_.push_back({Diagnostic::Severity::warning, std::move(where), std::move(message)});
}

void Diagnostics::note(Location where, std::string message) {
  std::lock_guard lock(mutex_);
  items_.push_back({Diagnostic::Severity::note, std::move(where), std::move(message)});
}

size_t Diagnostics::error_count() const {
  std::lock_guard lock(mutex_);
  size_t n = 0;
  for (const auto& d : items_) n += d.severity == Diagnostic::Severity::error;
  return n;
}

bool Diagnostics::has_errors() const {
  return error_count() > 0;
}

std::vector<Diagnostic> Diagnostics::all() const {
  std::lock_guard lock(mutex_);
  return items_;
}

void Diagnostics::print(std::ostream& out) const {
  // Shaders compile on several threads; sorting keeps the output the same from run to run.
  auto items = all();
  std::stable_sort(items.begin(), items.end(), [](const Diagnostic& a, const Diagnostic& b) {
    return std::tie(a.where.file, a.where.line, a.where.column) <
           std::tie(b.where.file, b.where.line, b.where.column);
  });
  for (const auto& d : items) out << format_diagnostic(d) << '\n';
}

}  // namespace statepack::packager
