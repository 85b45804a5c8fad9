#include "input_file.hpp"

namespace statepack::packager {

InputText read_input_file(const std::filesystem::path& path, const std::string& display, uint64_t max_bytes) {
  InputText out;
  // The size limit is the packager's option, so its message says how to raise it.
  auto file = detail::read_regular_file(path, max_bytes, display, " (--max-input-size sets the limit)");
  if (!file) {
    out.error = file.error().message;
    return out;
  }
  auto bytes = file->bytes();
  out.text.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  out.identity = file->identity;
  return out;
}

}  // namespace statepack::packager
