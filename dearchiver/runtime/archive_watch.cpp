// ArchiveFileWatch: notices a new build of an archive file in a running application. A poll is one
// stat(); only a file whose identity, size or times changed is read, and only a complete, valid archive
// with new bytes is handed back. A packer writes archives by rename (never half-written in place), but
// another writer may not: a file shorter than its header says is "still being written", not an error.
#include <sys/stat.h>

#include "api_guard.hpp"
#include "archive_access.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack {
using detail::api_guard;

namespace {

// What identifies one version of a file without reading it: a rename gives another inode, a write in
// place another size or modification time (nanoseconds), a change of either another ctime.
struct FileStamp {
  dev_t device = 0;
  ino_t inode = 0;
  off_t size = -1;
  timespec modified{}, changed{};
  bool operator==(const FileStamp& o) const {
    return device == o.device && inode == o.inode && size == o.size && modified.tv_sec == o.modified.tv_sec &&
           modified.tv_nsec == o.modified.tv_nsec && changed.tv_sec == o.changed.tv_sec &&
           changed.tv_nsec == o.changed.tv_nsec;
  }
};

std::optional<FileStamp> stamp_of(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileStamp{st.st_dev, st.st_ino, st.st_size, st.st_mtim, st.st_ctim};
}

// The error that means "not all of it is there yet" rather than "this is not an archive": a file that
// ends before what its header declares (an empty one included).
bool still_being_written(const Error& e) {
  return e.code == ErrorCode::truncated;
}

}  // namespace

struct ArchiveFileWatch::State {
  std::filesystem::path path;
  std::optional<uint32_t> required_content_version;
  std::optional<FileStamp> seen;  // the version of the file last looked at
  uint64_t loaded_hash = 0;       // the bytes of the archive last handed back (or there at create)
};

ArchiveFileWatch::ArchiveFileWatch(std::unique_ptr<State> state) : state_(std::move(state)) {}
ArchiveFileWatch::ArchiveFileWatch(ArchiveFileWatch&&) noexcept = default;
ArchiveFileWatch& ArchiveFileWatch::operator=(ArchiveFileWatch&&) noexcept = default;
ArchiveFileWatch::~ArchiveFileWatch() = default;

Result<ArchiveFileWatch> ArchiveFileWatch::create(std::filesystem::path path,
                                                  std::optional<uint32_t> required_content_version) {
  return api_guard("ArchiveFileWatch::create", [&]() -> Result<ArchiveFileWatch> {
    auto state = std::make_unique<State>();
    state->path = std::move(path);
    state->required_content_version = required_content_version;
    // The archive there now is the application's already: its stamp and bytes are the baseline. One
    // that does not load (missing, half written) leaves no baseline: the first complete one is new.
    state->seen = stamp_of(state->path);
    if (state->seen)
      if (auto current = Archive::from_file(state->path, required_content_version))
        state->loaded_hash = detail::ArchiveAccess::file_hash(*current);
    return ArchiveFileWatch(std::move(state));
  });
}

Result<std::optional<Archive>> ArchiveFileWatch::poll() {
  return api_guard("ArchiveFileWatch::poll", [&]() -> Result<std::optional<Archive>> {
    State& s = *state_;
    const std::optional<FileStamp> now = stamp_of(s.path);
    if (!now || now == s.seen) return std::optional<Archive>();
    auto archive = Archive::from_file(s.path, s.required_content_version);
    // The file may have changed while it was read: it is looked at again unless it still is as stamped.
    const bool steady = stamp_of(s.path) == now;
    if (!archive) {
      if (steady) s.seen = now;
      if (!steady || still_being_written(archive.error())) return std::optional<Archive>();
      return archive.error();
    }
    if (!steady) return std::optional<Archive>();
    s.seen = now;
    const uint64_t hash = detail::ArchiveAccess::file_hash(*archive);
    if (hash == s.loaded_hash) return std::optional<Archive>();  // rewritten with the same bytes
    s.loaded_hash = hash;
    return std::optional<Archive>(std::move(*archive));
  });
}

const std::filesystem::path& ArchiveFileWatch::path() const {
  return state_->path;
}

}  // namespace statepack
