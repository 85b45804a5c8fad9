#include "diagnostics.hpp"

#include <algorithm>
#include <cstdint>
#include <ostream>
#include <tuple>

namespace statepack::packager {

std::string location_text(const Location& where) {
  std::string text = where.file.empty() ? "statepack" : printable(where.file);
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
  text += printable(d.message);
  if (!d.where.pointer.empty()) text += " [" + printable(d.where.pointer) + "]";
  return text;
}

void Diagnostics::add(Diagnostic::Severity severity, Location where, std::string message) {
  std::lock_guard lock(mutex_);
  if (severity == Diagnostic::Severity::error) {
    ++errors_;
    if (max_errors_ != 0 && errors_ > max_errors_) {
      ++dropped_;
      return;
    }
  } else if (max_errors_ != 0 && items_.size() >= 10 * max_errors_) {
    ++dropped_others_;  // warnings and notes are bounded too
    return;
  }
  items_.push_back({severity, std::move(where), std::move(message)});
}

void Diagnostics::error(Location where, std::string message) {
  add(Diagnostic::Severity::error, std::move(where), std::move(message));
}

void Diagnostics::warning(Location where, std::string message) {
  add(Diagnostic::Severity::warning, std::move(where), std::move(message));
}

void Diagnostics::note(Location where, std::string message) {
  add(Diagnostic::Severity::note, std::move(where), std::move(message));
}

size_t Diagnostics::error_count() const {
  std::lock_guard lock(mutex_);
  return errors_;
}

bool Diagnostics::has_errors() const {
  return error_count() > 0;
}

bool Diagnostics::full() const {
  std::lock_guard lock(mutex_);
  return max_errors_ != 0 && errors_ >= max_errors_;
}

size_t Diagnostics::dropped_error_count() const {
  std::lock_guard lock(mutex_);
  return dropped_;
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
  std::lock_guard lock(mutex_);
  if (max_errors_ != 0 && errors_ >= max_errors_)
    out << "statepack: stopped after " << max_errors_ << " errors (--max-errors N sets the limit, 0 for none)"
        << (dropped_ > 0 ? "; " + std::to_string(dropped_) + " more not shown" : std::string()) << '\n';
  if (dropped_others_ > 0) out << "statepack: " << dropped_others_ << " more warnings and notes not shown\n";
}

}  // namespace statepack::packager
