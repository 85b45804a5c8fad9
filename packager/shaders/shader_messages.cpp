#include "shader_messages.hpp"

#include <algorithm>
#include <vector>

namespace statepack::packager {

namespace {

// An #include shared by dozens of shaders would make a line nobody reads: the first few, then a count.
constexpr size_t kNamesShown = 4;

std::string shader_list(const std::set<std::string>& names) {
  std::string text = names.size() == 1 ? "shader " : "shaders ";
  size_t i = 0;
  for (const auto& name : names) {
    if (i == kNamesShown) {
      text += " and " + std::to_string(names.size() - kNamesShown) + " more";
      break;
    }
    if (i > 0) text += (i + 1 == names.size() ? " and " : ", ");
    const bool opengl =
        name.size() >= sizeof(kOpenGlCompile) - 1 &&
        name.compare(name.size() - (sizeof(kOpenGlCompile) - 1), std::string::npos, kOpenGlCompile) == 0;
    text += opengl ? "'" + name.substr(0, name.size() - (sizeof(kOpenGlCompile) - 1)) + "'" + kOpenGlCompile
                   : "'" + name + "'";
    ++i;
  }
  return text;
}

}  // namespace

void ShaderMessages::error(const Location& where, const std::string& shader, const std::string& message,
                           size_t order) {
  std::lock_guard lock(mutex_);
  Shaders& entry = shaders_by_message_[{where.file, where.line, where.column, where.pointer, message}];
  entry.names.insert(shader);
  entry.order = std::min(entry.order, order);
}

bool ShaderMessages::empty() const {
  std::lock_guard lock(mutex_);
  return shaders_by_message_.empty();
}

void ShaderMessages::report(Diagnostics& diag) const {
  std::lock_guard lock(mutex_);
  std::vector<std::pair<const Key*, const Shaders*>> entries;
  for (const auto& [key, shaders] : shaders_by_message_) entries.push_back({&key, &shaders});
  // By place, then by log order; the map's order (the message text) breaks ties.
  std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    const auto& [fa, la, ca, pa, ma] = *a.first;
    const auto& [fb, lb, cb, pb, mb] = *b.first;
    return std::tie(fa, la, ca, pa, a.second->order) < std::tie(fb, lb, cb, pb, b.second->order);
  });
  for (const auto& [key, shaders] : entries) {
    const auto& [file, line, column, pointer, message] = *key;
    diag.error({file, line, column, pointer}, shader_list(shaders->names) + ": " + message);
  }
}

}  // namespace statepack::packager
