#include "shader_messages.hpp"

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
    text += "'" + name + "'";
    ++i;
  }
  return text;
}

}  // namespace

void ShaderMessages::error(const Location& where, const std::string& shader, const std::string& message) {
  std::lock_guard lock(mutex_);
  shaders_by_message_[{where.file, where.line, where.column, where.pointer, message}].insert(shader);
}

bool ShaderMessages::empty() const {
  std::lock_guard lock(mutex_);
  return shaders_by_message_.empty();
}

void ShaderMessages::report(Diagnostics& diag) const {
  std::lock_guard lock(mutex_);
  for (const auto& [key, shaders] : shaders_by_message_) {
    const auto& [file, line, column, pointer, message] = key;
    diag.error({file, line, column, pointer}, shader_list(shaders) + ": " + message);
  }
}

}  // namespace statepack::packager
