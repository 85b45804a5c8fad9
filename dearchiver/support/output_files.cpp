#include "output_files.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

namespace statepack::detail {
namespace fs = std::filesystem;
namespace {

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

fs::path directory_of(const fs::path& path) {
  fs::path dir = path.parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

std::string temp_prefix(const fs::path& path) {
  return "." + path.filename().string() + ".statepack-tmp-";
}

// A name for the next temporary of `path`; unique within this process, and the PID makes it unique
// across processes.
fs::path next_temp_name(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  return directory_of(path) /
         (temp_prefix(path) + std::to_string(::getpid()) + "-" + std::to_string(counter++));
}

// Removes ".NAME.statepack-tmp-PID-N" files whose process PID no longer exists.
void remove_stale_temporaries(const fs::path& path) {
  const std::string prefix = temp_prefix(path);
  DIR* dir = ::opendir(directory_of(path).c_str());
  if (!dir) return;
  while (dirent* entry = ::readdir(dir)) {
    std::string name = entry->d_name;
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    size_t i = prefix.size();
    long pid = 0;
    while (i < name.size() && name[i] >= '0' && name[i] <= '9' && pid < 1'000'000'000)
      pid = pid * 10 + (name[i++] - '0');
    if (i == prefix.size() || i >= name.size() || name[i] != '-' || pid <= 0) continue;
    if (pid == ::getpid() || ::kill(pid_t(pid), 0) == 0 || errno != ESRCH)
      continue;  // alive, or not ours to judge
    ::unlinkat(::dirfd(dir), name.c_str(), 0);
  }
  ::closedir(dir);
}

std::string write_all(int fd, std::span<const uint8_t> bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return std::generic_category().message(errno);
    done += size_t(n);
  }
  return "";
}

Error io_failure(std::string message) {
  return Error{ErrorCode::io_error, std::move(message)};
}

}  // namespace

OutputSet::~OutputSet() {
  for (auto& s : staged_) {
    if (s.fd >= 0) ::close(s.fd);
    if (!s.temp.empty()) ::unlink(s.temp.c_str());
  }
}

std::string OutputSet::refuse_reason(const fs::path& path) const {
  if (path.empty()) return "an output path is empty";
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode))
      return "refusing to write " + quoted(path) +
             ": it is a symbolic link, and statepack replaces outputs by renaming, which would replace the "
             "link rather than write its target; name the target itself";
    if (!S_ISREG(st.st_mode))
      return "refusing to write " + quoted(path) + ": it is " + file_kind(st.st_mode) +
             ", and outputs must be regular files";
    FileIdentity id{uint64_t(st.st_dev), uint64_t(st.st_ino)};
    for (const auto& input : inputs_)
      if (input.identity == id)
        return "refusing to write " + quoted(path) + ": it is the input " + quoted(input.path) +
               " of this run (the same file); statepack never replaces its inputs";
    for (const auto& other : staged_) {
      struct stat o {};
      if (::stat(other.path.c_str(), &o) == 0 && o.st_dev == st.st_dev && o.st_ino == st.st_ino)
        return "refusing to write " + quoted(path) + ": it is also the output " + quoted(other.path);
    }
  }
  std::error_code ec;
  fs::path canonical = fs::weakly_canonical(path, ec);
  for (const auto& other : staged_)
    if (!ec && fs::weakly_canonical(other.path, ec) == canonical)
      return "refusing to write " + quoted(path) + ": it is also the output " + quoted(other.path);
  return "";
}

Result<void> OutputSet::stage(const fs::path& path, std::span<const uint8_t> bytes) {
  if (std::string reason = refuse_reason(path); !reason.empty())
    return Error{ErrorCode::invalid_argument, std::move(reason)};
  remove_stale_temporaries(path);
  Staged s{path, -1, {}};
  // An unnamed file first: it cannot outlive this process.
  s.fd = ::open(directory_of(path).c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
  if (s.fd < 0) {
    if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)
      return io_failure("cannot create " + quoted(path) + ": " + std::generic_category().message(errno));
    // No O_TMPFILE on this file system: a new named file; O_EXCL never follows a planted symlink.
    for (int attempt = 0; attempt < 100 && s.fd < 0; ++attempt) {
      s.temp = next_temp_name(path);
      s.fd = ::open(s.temp.c_str(), O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0666);
      if (s.fd < 0 && errno != EEXIST) {
        std::string reason =
            "cannot create " + quoted(s.temp) + ": " + std::generic_category().message(errno);
        s.temp.clear();
        return io_failure(std::move(reason));
      }
    }
    if (s.fd < 0) return io_failure("cannot create a temporary beside " + quoted(path));
  }
  staged_.push_back(s);  // the destructor now cleans it up on any failure
  if (std::string reason = write_all(s.fd, bytes); !reason.empty())
    return io_failure("cannot write " + quoted(path) + ": " + reason);
  return {};
}

Result<void> OutputSet::commit() {
  // Give every unnamed temporary a name first, so a failure here still leaves every destination intact.
  for (auto& s : staged_) {
    if (!s.temp.empty()) continue;
    const std::string proc = "/proc/self/fd/" + std::to_string(s.fd);
    for (int attempt = 0; attempt < 100 && s.temp.empty(); ++attempt) {
      fs::path name = next_temp_name(s.path);
      // AT_EMPTY_PATH needs CAP_DAC_READ_SEARCH; /proc/self/fd works for everyone where /proc exists.
      if (::linkat(s.fd, "", AT_FDCWD, name.c_str(), AT_EMPTY_PATH) == 0 ||
          (errno != EEXIST &&
           ::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0))
        s.temp = name;
      else if (errno != EEXIST)
        return io_failure("cannot create " + quoted(name) + ": " + std::generic_category().message(errno));
    }
    if (s.temp.empty()) return io_failure("cannot create a temporary beside " + quoted(s.path));
  }
  for (auto& s : staged_) {
    if (::close(s.fd) != 0) {
      s.fd = -1;
      return io_failure("cannot write " + quoted(s.path) + ": " + std::generic_category().message(errno));
    }
    s.fd = -1;
  }
  for (auto& s : staged_) {
    if (::rename(s.temp.c_str(), s.path.c_str()) != 0)
      return io_failure("cannot replace " + quoted(s.path) + ": " + std::generic_category().message(errno));
    s.temp.clear();
  }
  staged_.clear();
  return {};
}

}  // namespace statepack::detail
