#include "file_io.hpp"

#include "output_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace statepack::detail {
namespace fs = std::filesystem;

namespace {

// The OS reason for errno, thread-safe (unlike strerror).
std::string os_reason(int error) {
  return std::generic_category().message(error);
}

}  // namespace

const char* file_kind(unsigned mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

namespace {

struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::optional<FileIdentity> file_identity(const fs::path& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return std::nullopt;
  return FileIdentity{uint64_t(info.st_dev), uint64_t(info.st_ino)};
}

Result<void> write_file_atomically(const fs::path& path, std::span<const uint8_t> bytes,
                                   const std::vector<fs::path>& inputs) {
  std::vector<InputFile> protected_inputs;
  for (const auto& input : inputs)
    if (auto id = file_identity(input)) protected_inputs.push_back({input, *id});
  OutputSet output(std::move(protected_inputs));
  if (auto staged = output.stage(path, bytes); !staged) return staged;
  return output.commit();
}

Result<void> save_file_atomically(const fs::path& path, std::span<const uint8_t> bytes) {
  auto written = write_file_atomically(path, bytes);
  if (!written && written.error().code == ErrorCode::invalid_argument)
    return Error{ErrorCode::io_error, written.error().message};
  return written;
}

Result<FileBytes> read_regular_file(const fs::path& path, uint64_t max_size, const std::string& display,
                                    std::string_view size_hint) {
  const std::string name = display.empty() ? path.string() : display;
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer forever.
  Descriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)};
  if (file.fd < 0) return Error{ErrorCode::io_error, name + ": cannot open: " + os_reason(errno)};
  struct stat info {};
  if (::fstat(file.fd, &info) != 0)
    return Error{ErrorCode::io_error, name + ": cannot stat: " + os_reason(errno)};
  if (!S_ISREG(info.st_mode))
    return Error{ErrorCode::io_error,
                 name + ": cannot read: it is " + file_kind(info.st_mode) + ", not a regular file"};
  const auto size = static_cast<uint64_t>(info.st_size);
  if (size > max_size)
    return Error{ErrorCode::io_error, name + ": cannot read: " + std::to_string(size) +
                                          " bytes is more than the " + std::to_string(max_size) +
                                          " bytes allowed" + std::string(size_hint)};
  FileBytes out;
  out.identity = {uint64_t(info.st_dev), uint64_t(info.st_ino)};
  out.size = static_cast<size_t>(size);
  out.words.resize((out.size + 3) / 4);
  auto* cursor = reinterpret_cast<uint8_t*>(out.words.data());
  // The read is bounded by the size fstat gave: a file that grows meanwhile cannot make us read more.
  size_t done = 0;
  while (done < out.size) {
    ssize_t n = ::read(file.fd, cursor + done, out.size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Error{ErrorCode::io_error, name + ": cannot read: " + os_reason(errno)};
    if (n == 0)
      return Error{ErrorCode::io_error, name + ": cannot read: the file shrank from " +
                                            std::to_string(out.size) + " to " + std::to_string(done) +
                                            " bytes while being read"};
    done += static_cast<size_t>(n);
  }
  return out;
}

}  // namespace statepack::detail
