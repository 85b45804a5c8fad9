#include "file_io.hpp"

#include <unistd.h>

#include <fstream>

namespace statepack {
namespace fs = std::filesystem;

std::string write_file_atomically(const fs::path& path, std::span<const uint8_t> bytes) {
  fs::path temp = path;
  temp += ".tmp-" + std::to_string(::getpid());
  std::error_code ec;
  {
    std::ofstream file(temp, std::ios::binary | std::ios::trunc);
    if (!file) return "cannot create '" + temp.string() + "'";
    file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.flush();
    if (!file) {
      fs::remove(temp, ec);
      return "cannot write '" + temp.string() + "'";
    }
  }
  fs::rename(temp, path, ec);
  if (ec) {
    std::string reason = "cannot rename '" + temp.string() + "' to '" + path.string() + "': " + ec.message();
    fs::remove(temp, ec);
    return reason;
  }
  return "";
}

std::optional<std::vector<uint8_t>> read_file(const fs::path& path) {
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) return std::nullopt;
  std::vector<uint8_t> bytes(static_cast<size_t>(file.tellg()));
  file.seekg(0);
  if (!file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
    return std::nullopt;
  return bytes;
}

}  // namespace statepack
