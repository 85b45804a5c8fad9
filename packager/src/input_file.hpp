// Reading the packager's inputs (notation files, shaders, #includes) without trusting them: a read never
// blocks (FIFOs and devices are refused before any byte is read), never follows a size the file does not
// have, and every failure names the OS's reason. Each file read is remembered by identity (device and
// inode), so outputs can refuse to replace any input however its path is spelled.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>

namespace statepack::packager {

// Inputs larger than this are refused: no notation file or shader is anywhere near it, and reading one
// must not exhaust memory.
inline constexpr uint64_t kMaxInputBytes = 64ull << 20;

struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
  auto operator<=>(const FileIdentity&) const = default;
};

struct InputText {
  std::string text;
  std::string error;  // empty on success; else "cannot read 'x': reason"
  FileIdentity identity;
};

// Reads a whole regular file of at most `max_bytes`; messages name it `display` (default: the path).
InputText read_input_file(const std::filesystem::path& path, const std::string& display = {},
                          uint64_t max_bytes = kMaxInputBytes);

// "a directory", "a FIFO", "a character device", ... for messages about non-regular files.
std::string file_type_name(mode_t mode);

// A file a run read, by path (for the depfile and messages) and identity (to protect it from outputs).
struct InputFile {
  std::filesystem::path path;
  FileIdentity identity;
};

}  // namespace statepack::packager
