#include "diagnostics.hpp"

#include <algorithm>
#include <cstdint>
#include <ostream>
#include <tuple>

namespace statepack::packager {

std::string printable(std::string_view text) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  auto escape = [&](unsigned char c) { out += "\\x", out += kHex[c >> 4], out += kHex[c & 0xF]; };
  for (size_t i = 0; i < text.size();) {
    auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      if (c < 0x20 || c == 0x7F)
        escape(c);
      else
        out += char(c);
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence (no overlongs, no surrogates, at most U+10FFFF) passes unchanged.
    size_t length = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    bool ok = length > 0 && i + length <= text.size();
    for (size_t k = 1; ok && k < length; ++k) ok = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
    if (ok && length >= 3) {
      auto c1 = static_cast<unsigned char>(text[i + 1]);
      ok = !(c == 0xE0 && c1 < 0xA0) && !(c == 0xED && c1 >= 0xA0) && !(c == 0xF0 && c1 < 0x90) &&
           !(c == 0xF4 && c1 >= 0x90);
    }
    // C1 control characters (U+0080..U+009F) can act as terminal escapes too.
    if (ok && length == 2 && c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0) ok = false;
    if (!ok) {
      escape(c);
      ++i;
      continue;
    }
    out.append(text, i, length);
    i += length;
  }
  return out;
}

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
