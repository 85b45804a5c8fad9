#include "watch.hpp"

#include <malloc.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/signalfd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "pack/compiler_warmup.hpp"
#include "pack/repack_memo.hpp"
#include "shaders/compile_cache.hpp"

namespace statepack::packager {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

// Without --cache-dir, compiled shaders are kept in memory between repacks, up to this much.
constexpr uint64_t kMemoryCacheBytes = uint64_t(256) << 20;

// What a watched directory reports: a file in it written (closed after writing, or modified while
// open), created, deleted, renamed into it (an editor's save by rename) or out of it; and the directory
// itself deleted or moved away.
constexpr uint32_t kWatchMask = IN_CLOSE_WRITE | IN_MODIFY | IN_CREATE | IN_DELETE | IN_MOVED_FROM |
                                IN_MOVED_TO | IN_DELETE_SELF | IN_MOVE_SELF | IN_ONLYDIR;

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

// A path as it is watched: absolute and lexically normal.
fs::path normal(const fs::path& path) {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  return (ec ? path : absolute).lexically_normal();
}

bool directory_exists(const fs::path& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

// The directories to watch for a set of files, each with the names in it that matter. The directory of
// a file that is not there is stood in for by its nearest existing ancestor, which watches for the next
// name on the way down, so that the directory's return is seen.
struct WatchPlan {
  std::map<fs::path, std::set<std::string>> names;  // by directory
  std::map<fs::path, fs::path> stand_ins;           // a file's missing directory -> the one watched
};

WatchPlan plan_watches(const std::set<fs::path>& files) {
  WatchPlan plan;
  for (const fs::path& file : files) {
    fs::path dir = file.parent_path(), name = file.filename();
    while (!directory_exists(dir) && dir.has_relative_path()) {  // "/" is always there
      name = dir.filename();
      dir = dir.parent_path();
    }
    if (dir != file.parent_path()) plan.stand_ins[file.parent_path()] = dir;
    plan.names[dir].insert(name.string());
  }
  return plan;
}

// What the events read since the last repack say.
struct Changes {
  std::set<fs::path> paths;  // watched files (or directories on their way) written, created or gone
  bool lost = false;         // the kernel's event queue overflowed: anything may have changed
  bool rewatch = false;      // a watched directory went, or one that was missing came: watch() again
  bool any() const { return lost || !paths.empty(); }
};

// inotify on the directories of a set of files: directories, not files, so that a save by rename, and a
// delete and re-create, are seen; events on other names in them are ignored.
class DirectoryWatcher {
 public:
  explicit DirectoryWatcher(int fd) : fd_(fd) {}
  int fd() const { return fd_.get(); }
  size_t directories() const { return by_wd_.size(); }

  // Watches the directories of `files` (the nearest existing ancestor of one that is missing) and no
  // other. Says on `err` when the directory of watched files has gone, or is back.
  void watch(const std::set<fs::path>& files, std::ostream& err) {
    const WatchPlan plan = plan_watches(files);
    std::map<int, Watched> next;
    for (const auto& [dir, names] : plan.names) {
      // The same directory again keeps its watch descriptor: no event is lost in between.
      const int wd = ::inotify_add_watch(fd_.get(), dir.c_str(), kWatchMask);
      if (wd < 0) {
        if (refused_.insert(dir).second)
          err << "statepack: warning: --watch: cannot watch '" << printable(display_path(dir))
              << "': " << std::strerror(errno)
              << (errno == ENOSPC ? " (the limit is /proc/sys/fs/inotify/max_user_watches)" : "")
              << "; changes of files in it are not seen\n";
        continue;
      }
      refused_.erase(dir);
      Watched& watched = next[wd];
      if (watched.dir.empty()) watched.dir = dir;  // one directory by two names: either will do
      watched.names.insert(names.begin(), names.end());
    }
    for (const auto& [wd, watched] : by_wd_)
      if (!next.count(wd)) ::inotify_rm_watch(fd_.get(), wd);  // its IN_IGNORED then matches nothing
    by_wd_ = std::move(next);
    for (const auto& [dir, stand_in] : plan.stand_ins)
      if (!first_ && gone_.insert(dir).second)
        err << "statepack: warning: --watch: the directory '" << printable(display_path(dir))
            << "' of watched files is gone; watching '" << printable(display_path(stand_in))
            << "' for its return\n";
    for (auto it = gone_.begin(); it != gone_.end();)
      if (plan.stand_ins.count(*it)) {
        ++it;
      } else {
        err << "statepack: --watch: the directory '" << printable(display_path(*it))
            << "' is back; watching it again\n";
        it = gone_.erase(it);
      }
    first_ = false;
  }

  // Reads every pending event into `changes`; whether one of them was about a watched name.
  bool read_events(Changes& changes) {
    bool relevant = false;
    alignas(inotify_event) char buffer[64 * 1024];
    for (;;) {
      const ssize_t n = ::read(fd_.get(), buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return relevant;  // EAGAIN: nothing more
      for (size_t at = 0; at + sizeof(inotify_event) <= size_t(n);) {
        inotify_event event;
        std::memcpy(&event, buffer + at, sizeof event);
        const char* name = buffer + at + sizeof event;
        at += sizeof event + event.len;
        relevant |= take(event, std::string(name, ::strnlen(name, event.len)), changes);
      }
    }
  }

 private:
  struct Watched {
    fs::path dir;
    std::set<std::string> names;  // of watched files, or of the next directory down to a missing one
  };

  bool take(const inotify_event& event, const std::string& name, Changes& changes) {
    if (event.mask & IN_Q_OVERFLOW) {
      changes.lost = changes.rewatch = true;
      return true;
    }
    auto it = by_wd_.find(event.wd);
    if (it == by_wd_.end()) return false;  // a watch watch() has removed
    if (event.mask & (IN_DELETE_SELF | IN_MOVE_SELF | IN_UNMOUNT | IN_IGNORED)) {
      changes.paths.insert(it->second.dir / "");  // "shaders/": a directory
      changes.rewatch = true;
      if (event.mask & IN_IGNORED) by_wd_.erase(it);  // the kernel has dropped it
      return true;
    }
    if (name.empty() || !it->second.names.count(name)) return false;
    if (event.mask & IN_ISDIR) {  // a directory on the way came or went
      changes.paths.insert(it->second.dir / name / "");
      changes.rewatch = true;
    } else {
      changes.paths.insert(it->second.dir / name);
    }
    return true;
  }

  FileDescriptor fd_;
  std::map<int, Watched> by_wd_;
  std::set<fs::path> refused_;  // directories inotify refused (reported once)
  std::set<fs::path> gone_;     // directories of watched files reported gone
  bool first_ = true;           // the first watch() reports nothing gone: it was never there
};

std::string seconds_since(Clock::time_point start) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(3) << std::chrono::duration<double>(Clock::now() - start).count()
       << " s";
  return text.str();
}

// "changed: shaders/pt.comp, common.glsl (gone)": at most three names, then how many more.
std::string describe(const Changes& changes) {
  if (changes.lost) return "changed: unknown, too many events at once";
  std::string text = "changed: ";
  size_t shown = 0;
  for (const fs::path& path : changes.paths) {
    if (shown == 3) {
      text += ", and " + std::to_string(changes.paths.size() - shown) + " more";
      break;
    }
    std::error_code ec;
    const bool there = fs::exists(fs::symlink_status(path, ec));
    text += (shown++ ? ", " : "") + printable(display_path(path)) + (there ? "" : " (gone)");
  }
  return text;
}

// The packs of a watch: the options, the cache kept between them, and the files to watch.
class Repacker {
 public:
  Repacker(const PackOptions& options, std::ostream& out, std::ostream& err)
      : options_(options), out_(out), err_(err) {
    // Without --cache-dir, compiled and finalised SPIR-V stays in memory from one pack to the next.
    if (!options.cache_dir) memory_cache_.emplace(CompileCache::in_memory(kMemoryCacheBytes));
    session_.cache = memory_cache_ ? &*memory_cache_ : nullptr;
    session_.memo = &memo_;
    // The notation files as given, wherever -i may find them: watched even when not there (yet).
    for (const auto& input : options.inputs) {
      base_files_.insert(normal(input));
      if (input.is_relative())
        for (const auto& dir : options.notation.render_state_dirs) base_files_.insert(normal(dir / input));
    }
    files_ = base_files_;
    update_watched();
  }

  // One pack; its exit code. The files to watch become what it read (with those given as -i); after a
  // failure, what it read is added to what was watched: a file it did not get to (a shader deleted,
  // one past a syntax error) stays watched, so that the fix is seen.
  int pack() {
    const int code = run_pack(options_, out_, err_, &session_);
    if (code == kExitSuccess) files_ = base_files_;
    for (const fs::path& read : session_.files_read) files_.insert(normal(read));
    update_watched();
    return code;
  }

  // glslang's built-in tables (~50 ms, once per process) for the project's first shader, unless the
  // first pack built them: a first pack whose shaders all came from the cache compiled nothing, and the
  // first edit would wait for them. Built while the watch waits (an edit meanwhile is queued, not lost).
  void prepare_compiler_for_edits() {
    try {  // (a speed-up only: what fails here, the compile meets and reports)
      if (const auto notation = memo_.notation())
        if (const ShaderDesc* shader = likely_compile(*notation, std::nullopt))
          prepare_compiler(*shader, options_.compile);
    } catch (...) {
    }
  }

  // What a failed pack leaves at the output.
  std::string kept() const {
    std::error_code ec;
    return fs::exists(options_.output, ec) ? "keeping the last archive" : "no archive written";
  }
  std::string archive_name() const { return printable(display_path(options_.output)); }
  // The paths to watch: each file, and the file a link (or a directory on its path) leads to, since an
  // edit of that is an edit of the input.
  const std::set<fs::path>& watched() const { return watched_; }
  size_t file_count() const { return file_count_; }

 private:
  // After every pack (a link may lead elsewhere now). A file's real path is its directory's, resolved
  // once per directory, and its own name unless that is a link: an lstat per file instead of a readlink
  // per component of its path (1,000 shaders: about 12 ms of a 70 ms repack).
  void update_watched() {
    watched_ = files_;
    std::set<fs::path> there;
    std::map<fs::path, std::optional<fs::path>> real_directories;
    for (const fs::path& file : files_) {
      struct stat st {};
      if (::lstat(file.c_str(), &st) != 0) continue;  // (not there: canonical would fail too)
      std::error_code ec;
      fs::path target;
      if (S_ISLNK(st.st_mode)) {
        target = fs::canonical(file, ec);
        if (ec) continue;
      } else {
        auto [directory, added] = real_directories.try_emplace(file.parent_path());
        if (added)
          if (fs::path real = fs::canonical(file.parent_path(), ec); !ec) directory->second = std::move(real);
        if (!directory->second) continue;
        target = *directory->second / file.filename();
      }
      watched_.insert(target);
      there.insert(target);
    }
    file_count_ = there.size();
  }

  const PackOptions& options_;
  std::ostream& out_;
  std::ostream& err_;
  std::optional<CompileCache> memory_cache_;
  RepackMemo memo_;
  PackSession session_;
  std::set<fs::path> base_files_, files_, watched_;
  size_t file_count_ = 0;  // of the files there, by their real paths: one file by two names is one
};

// The wait between packs: events gathered until `quiet_ms` pass without one, or a stop signal.
class WatchLoop {
 public:
  WatchLoop(const PackOptions& options, const WatchOptions& watch, int signal_fd, int inotify_fd,
            std::ostream& out, std::ostream& err)
      : watch_(watch),
        signal_fd_(signal_fd),
        watcher_(inotify_fd),
        repacker_(options, out, err),
        out_(out),
        err_(err) {}

  int run() {
    const auto start = Clock::now();
    const int code = repacker_.pack();
    if (code == kExitUsage) return kExitUsage;  // refused before any work: every repack would be too
    watcher_.watch(repacker_.watched(), err_);
    out_ << (code == kExitSuccess ? "packed " + repacker_.archive_name() + " in " + seconds_since(start)
                                  : "pack failed in " + seconds_since(start) + "; " + repacker_.kept())
         << "; watching " << repacker_.file_count() << " file(s) in " << watcher_.directories() << " director"
         << (watcher_.directories() == 1 ? "y" : "ies") << " (Ctrl-C to stop)" << std::endl;
    repacker_.prepare_compiler_for_edits();
    for (;;) {
      if (std::optional<int> stopped = wait_for_changes()) {
        out_ << "stopped by " << signal_name(*stopped) << std::endl;
        return kExitSuccess;
      }
      repack();
    }
  }

 private:
  // Gathers events until a change has been followed by `quiet_ms` without another; the stop signal's
  // number if one comes first.
  std::optional<int> wait_for_changes() {
    changes_ = {};
    Clock::time_point deadline{};
    for (;;) {
      int timeout = -1;
      if (changes_.any()) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (left <= 0) return std::nullopt;
        timeout = int(left);
      }
      pollfd fds[2] = {{signal_fd_, POLLIN, 0}, {watcher_.fd(), POLLIN, 0}};
      if (::poll(fds, 2, timeout) < 0) {
        if (errno == EINTR) continue;
        err_ << "statepack: error: --watch: poll: " << std::strerror(errno) << '\n';
        return SIGTERM;
      }
      if (fds[0].revents) {
        signalfd_siginfo info{};
        if (::read(signal_fd_, &info, sizeof info) == ssize_t(sizeof info)) return int(info.ssi_signo);
      }
      if (fds[1].revents & POLLIN) {
        changes_.rewatch = false;
        // Only an event about a watched file starts (or restarts) the quiet period.
        if (watcher_.read_events(changes_))
          deadline = Clock::now() + std::chrono::milliseconds(watch_.quiet_ms);
        if (changes_.rewatch) watcher_.watch(repacker_.watched(), err_);
      }
    }
  }

  void repack() {
    const auto start = Clock::now();
    const int code = repacker_.pack();
    watcher_.watch(repacker_.watched(), err_);
    if (code == kExitSuccess)
      out_ << "repacked " << repacker_.archive_name() << " in " << seconds_since(start) << " ("
           << describe(changes_) << ")" << std::endl;
    else
      out_ << "pack failed in " << seconds_since(start) << " (" << describe(changes_) << "); "
           << repacker_.kept() << std::endl;
  }

  static std::string signal_name(int signal) {
    return signal == SIGINT    ? "SIGINT"
           : signal == SIGTERM ? "SIGTERM"
           : signal == SIGHUP  ? "SIGHUP"
                               : "a signal";
  }

  const WatchOptions& watch_;
  int signal_fd_;
  DirectoryWatcher watcher_;
  Repacker repacker_;
  Changes changes_;
  std::ostream& out_;
  std::ostream& err_;
};

// The heap a pack used stays mapped for the next: glibc would otherwise hand large blocks and the free
// top of each heap back to the kernel after every pack, and the next pack fault them in again, page by
// page (a repack of 300 real-sized shaders varied from 190 to 340 ms with it, 166 to 189 without). The
// watch's resident memory stays near a pack's peak instead. GLIBC_TUNABLES naming malloc settings wins.
void keep_heap_between_packs() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::strstr(tunables, "malloc")) return;
  ::mallopt(M_MMAP_THRESHOLD, 32 << 20);  // (glibc's largest: blocks under it come from the heaps)
  ::mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

}  // namespace

int run_watch(const PackOptions& options, const WatchOptions& watch, std::ostream& out, std::ostream& err) {
  keep_heap_between_packs();
  // The stop signals are blocked before the first pack starts its threads (which inherit the mask), and
  // read from a signalfd between packs: a pack under way always finishes, so no temporary is left.
  sigset_t stop, before;
  sigemptyset(&stop);
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&stop, signal);
  if (int failed = ::pthread_sigmask(SIG_BLOCK, &stop, &before); failed != 0) {
    err << "statepack: error: --watch: cannot block signals: " << std::strerror(failed) << '\n';
    return kExitIoError;
  }
  int code = kExitIoError;
  {
    FileDescriptor signals(::signalfd(-1, &stop, SFD_NONBLOCK | SFD_CLOEXEC));
    const int inotify = signals.get() < 0 ? -1 : ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (inotify < 0)
      err << "statepack: error: --watch: cannot "
          << (signals.get() < 0 ? "create a signalfd" : "start inotify") << ": " << std::strerror(errno)
          << '\n';
    else
      code = WatchLoop(options, watch, signals.get(), inotify, out, err).run();
  }
  ::pthread_sigmask(SIG_SETMASK, &before, nullptr);
  return code;
}

}  // namespace statepack::packager
