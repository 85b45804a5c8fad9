#include "input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace statepack::packager {

std::string file_type_name(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

InputText read_input_file(const std::filesystem::path& path, const std::string& display, uint64_t max_bytes) {
  InputText out;
  const std::string name = "'" + (display.empty() ? path.string() : display) + "'";
  // O_NONBLOCK: opening a FIFO with no writer would otherwise wait forever; regular files ignore it.
  int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    out.error = "cannot open " + name + ": " + std::strerror(errno);
    return out;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    out.error = "cannot read " + name + ": " + std::strerror(errno);
  } else if (!S_ISREG(st.st_mode)) {
    out.error = "cannot read " + name + ": it is " + file_type_name(st.st_mode) + ", not a regular file";
  } else if (uint64_t(st.st_size) > max_bytes) {
    out.error = "cannot read " + name + ": it is " + std::to_string(st.st_size) + " bytes, more than the " +
                std::to_string(max_bytes) + " an input may have";
  } else {
    out.identity = {st.st_dev, st.st_ino};
    out.text.resize(size_t(st.st_size));
    size_t done = 0;
    // Reads what fstat promised and no more: a file that shrinks is an error, one that grows is cut.
    while (done < out.text.size()) {
      ssize_t n = ::read(fd, out.text.data() + done, out.text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        out.error = "cannot read " + name + ": " + std::strerror(errno);
        break;
      }
      if (n == 0) {
        out.error = "cannot read " + name + ": it shrank while being read";
        break;
      }
      done += size_t(n);
    }
  }
  ::close(fd);
  if (!out.error.empty()) out.text.clear();
  return out;
}

}  // namespace statepack::packager
