// Reading the packager's inputs (notation files, shaders, #includes) as text, through the dearchiver's
// bounded reader: a read never blocks (FIFOs and devices are refused before any byte is read), never
// reads more than the file's size, and every failure names the OS's reason. The identity of each file
// read is kept, so outputs can refuse to replace any input however its path is spelled.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "support/file_io.hpp"
#include "support/output_files.hpp"

namespace statepack::packager {

using statepack::detail::FileIdentity;
using statepack::detail::InputFile;

// Inputs larger than this are refused unless --max-input-size raises it: no notation file or shader is
// anywhere near it, and reading one must not exhaust memory.
inline constexpr uint64_t kMaxInputBytes = 64ull << 20;

struct InputText {
  std::string text;
  std::string error;  // empty on success; else "NAME: cannot read: reason"
  FileIdentity identity;
};

// Reads a whole regular file of at most `max_bytes`; messages name it `display` (default: the path).
InputText read_input_file(const std::filesystem::path& path, const std::string& display = {},
                          uint64_t max_bytes = kMaxInputBytes);

}  // namespace statepack::packager
