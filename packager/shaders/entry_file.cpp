#include "entry_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "support/printable.hpp"

namespace statepack::packager {

namespace {
const std::string& host_name() {
  static const std::string name = [] {
    char text[256] = {};
    if (::gethostname(text, sizeof text - 1) != 0) return std::string("host");
    std::string out;
    for (const char* c = text; *c; ++c) out += std::isalnum(static_cast<unsigned char>(*c)) ? *c : '_';
    return out;
  }();
  return name;
}
}  // namespace

bool write_beside_and_rename(const std::filesystem::path& path, std::span<const uint8_t> bytes,
                             std::string& error) {
  return write_beside_and_rename(path, std::vector<std::span<const uint8_t>>{bytes}, error);
}

bool write_beside_and_rename(const std::filesystem::path& path, std::vector<std::span<const uint8_t>> parts,
                             std::string& error) {
  static std::atomic<uint64_t> counter{0};
  const std::string name = path.filename().string();
  const std::filesystem::path temporary =
      path.parent_path() / (".tmp-" + host_name() + "-" + std::to_string(::getpid()) + "-" +
                            std::to_string(counter++) + "-" + name.substr(0, 8));
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    error = "cannot write '" + detail::printable(temporary.string()) + "': " + std::strerror(errno);
    return false;
  }
  int failure = 0;  // the errno of the first call that failed
  for (std::span<const uint8_t> bytes : parts) {
    size_t written = 0;
    while (!failure && written < bytes.size()) {
      const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        failure = n < 0 ? errno : ENOSPC;
      else
        written += size_t(n);
    }
  }
  if (::close(fd) != 0 && !failure) failure = errno;
  // rename() replaces a link planted at `path` rather than following it.
  if (!failure && ::rename(temporary.c_str(), path.c_str()) != 0) failure = errno;
  if (failure) {
    error = "cannot write '" + detail::printable(path.string()) + "': " + std::strerror(failure);
    ::unlink(temporary.c_str());
    return false;
  }
  return true;
}

EntryRead read_entry_file(const std::filesystem::path& path, uint64_t max_bytes, std::vector<uint8_t>& out) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return errno == ENOENT ? EntryRead::missing : EntryRead::unusable;
  struct stat st {};
  bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && uint64_t(st.st_size) <= max_bytes;
  if (ok) {
    out.resize(size_t(st.st_size));
    size_t done = 0;  // (a file that shrank underneath is a short read: unusable)
    while (done < out.size()) {
      const ssize_t n = ::read(fd, out.data() + done, out.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += size_t(n);
    }
    ok = done == out.size();
  }
  ::close(fd);
  return ok ? EntryRead::ok : EntryRead::unusable;
}

}  // namespace statepack::packager
