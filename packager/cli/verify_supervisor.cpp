// statepack verify, isolated: objects are created by worker processes (this program again, with the
// hidden --worker-start option), so a driver that crashes or hangs while creating one object fails
// that object, and a new worker goes on from the next one, as fossilize-replay does. The worker prints
// the human report on the shared stdout and tells the supervisor what it is doing on a pipe (fd 3):
//
// | line (worker to supervisor)  | meaning                                                          |
// |------------------------------|------------------------------------------------------------------|
// | `ready U`                    | the device exists (and the pipeline cache is loaded); U variants  |
// |                              | (--variants) have a pipeline no archive has: FAILED, counted once |
// | `archive A N`                | archive A (index on the command line) is read; it has N objects   |
// | `begin A O WHAT`             | creating object O of archive A; WHAT as the report names it       |
// | `end A O ok P T D F H` / `end A O failed ...` | that object's lines are on stdout; P pipelines |
// |                              | created (0 or 1), T ns, D ns of the driver's feedback, F with     |
// |                              | feedback, H from the pipeline cache (VerifyTotals)              |
// | `done A`                     | archive A's objects are destroyed and its leaks reported; the     |
// |                              | worker waits for one byte on fd 4 (the supervisor's, once it has  |
// |                              | printed A's summary), so the summary is in its place on stdout    |
//
// A worker that dies between `begin` and `end`, or says nothing for --timeout seconds, is the driver's
// fault for that object: FAILED, with the signal or the time, and verify resumes after it.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <optional>
#include <ostream>
#include <sstream>

#include "layout/format_support.hpp"
#include "notation/diagnostics.hpp"
#include "pack/packer.hpp"
#include "verify.hpp"

extern char** environ;

namespace statepack::packager {
namespace {

using Position = VerifyOptions::Position;

struct Worker {
  pid_t pid = -1;
  int control = -1;  // read end of the worker's fd 3
  int ack = -1;      // our end of the worker's fd 4
};

std::vector<std::string> worker_arguments(const VerifyOptions& options, Position start) {
  std::vector<std::string> args = {
      "statepack",      "verify",
      "--worker-start", std::to_string(start.archive) + ":" + std::to_string(start.object),
      "--format",       format_name(options.color_format)};
  if (options.device_index >= 0) args.insert(args.end(), {"--device", std::to_string(options.device_index)});
  if (options.cache) args.insert(args.end(), {"--cache", options.cache->string()});
  if (options.variants) args.insert(args.end(), {"--variants", options.variants->string()});
  if (!options.validation) args.emplace_back("--no-validation");
  args.emplace_back("--");  // archive names that begin with '-' stay names
  for (const auto& path : options.archives) args.push_back(path.string());
  return args;
}

// Starts a worker with its control pipe on kVerifyControlFd; the error text when it cannot.
std::optional<Worker> spawn_worker(const VerifyOptions& options, Position start, std::string& error) {
  int ends[2];
  if (::pipe2(ends, O_CLOEXEC) != 0) {
    error = std::string("cannot create a pipe: ") + std::strerror(errno);
    return std::nullopt;
  }
  // A socket for the acknowledgements: sent with MSG_NOSIGNAL, so a worker that died is no SIGPIPE.
  int ack[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ack) != 0) {
    error = std::string("cannot create a socket pair: ") + std::strerror(errno);
    ::close(ends[0]);
    ::close(ends[1]);
    return std::nullopt;
  }
  // Above both fds, so that the dup2s below always make fresh descriptors without CLOEXEC.
  const int write_end = ::fcntl(ends[1], F_DUPFD_CLOEXEC, kVerifyAckFd + 1);
  ::close(ends[1]);
  const int ack_end = ::fcntl(ack[1], F_DUPFD_CLOEXEC, kVerifyAckFd + 1);
  ::close(ack[1]);
  std::vector<std::string> args = worker_arguments(options, start);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, write_end, kVerifyControlFd);
  posix_spawn_file_actions_adddup2(&actions, ack_end, kVerifyAckFd);
  pid_t pid = -1;
  const int failed = ::posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(write_end);
  ::close(ack_end);
  if (failed != 0) {
    ::close(ends[0]);
    ::close(ack[0]);
    error = std::string("cannot start a worker process: ") + std::strerror(failed);
    return std::nullopt;
  }
  return Worker{pid, ends[0], ack[0]};
}

std::string signal_text(int signal) {
  const char* abbrev = ::sigabbrev_np(signal);
  return (abbrev ? "SIG" + std::string(abbrev) : "signal " + std::to_string(signal)) + ": " +
         ::strsignal(signal);
}

// What one worker did, from its control lines.
struct WorkerRun {
  bool ready = false;
  bool progressed = false;             // an object ended or an archive was done
  std::optional<std::string> pending;  // WHAT of an object begun and not ended
  Position resume;                     // where the next worker starts
  bool hung = false;
  int status = 0;  // waitpid's
  int ack = -1;    // where `done` is acknowledged
};

class Supervisor {
 public:
  Supervisor(const VerifyOptions& options, std::ostream& out, std::ostream& err)
      : options_(options), out_(out), err_(err), totals_(options.archives.size()) {}

  int run() {
    Position next;
    for (;;) {
      out_.flush();
      err_.flush();
      std::string error;
      auto worker = spawn_worker(options_, next, error);
      if (!worker) {
        err_ << "statepack: error: " << error << '\n';
        return std::max(exit_code_, int(kExitIoError));
      }
      WorkerRun run = watch(*worker, next);
      const std::string reason = death_reason(run);
      if (reason.empty() && !run.pending) {
        if (wants_in_all_line(options_.archives.size(), unresolved_) && run.ready) {
          VerifyTotals all;
          all.objects = unresolved_;
          for (const auto& t : totals_) all.add(t);
          out_ << "in all: " << all.summary() << '\n';
        }
        return std::max(exit_code_, WEXITSTATUS(run.status));
      }
      exit_code_ = std::max(exit_code_, int(kExitInputError));
      if (run.pending) {  // the driver's fault for that object; go on after it
        out_ << "FAILED " << *run.pending << ": " << reason
             << " while creating it; verify went on in a new process\n";
        next = run.resume;
        continue;
      }
      if (!run.ready) {
        err_ << "statepack: error: cannot create a Vulkan device: " << reason << '\n';
        return std::max(exit_code_, int(kExitIoError));
      }
      if (run.resume.archive >= options_.archives.size()) {
        out_ << "FAILED device teardown: " << reason << '\n';
        return exit_code_;
      }
      out_ << "FAILED " << printable(options_.archives[run.resume.archive].string()) << ": " << reason
           << " outside any object (reading the archive or destroying its objects)\n";
      // Once more from where it stopped if it got somewhere; else past that archive.
      next = run.progressed ? run.resume : Position{run.resume.archive + 1, 0};
    }
  }

 private:
  std::string death_reason(const WorkerRun& run) const {
    if (run.hung)
      return "no answer within " + std::to_string(options_.timeout_seconds) +
             " s (--timeout): the driver hung";
    if (WIFSIGNALED(run.status)) return "the driver crashed (" + signal_text(WTERMSIG(run.status)) + ")";
    if (run.pending) return "the worker exited with status " + std::to_string(WEXITSTATUS(run.status));
    return "";
  }

  WorkerRun watch(const Worker& worker, Position start) {
    WorkerRun run;
    run.resume = start;
    run.ack = worker.ack;
    std::string buffer;
    for (;;) {
      pollfd fd{worker.control, POLLIN, 0};
      const int timeout_ms = int(std::min<unsigned>(options_.timeout_seconds, 86400u) * 1000u);
      const int polled = ::poll(&fd, 1, timeout_ms);
      if (polled < 0 && errno == EINTR) continue;
      if (polled == 0) {
        run.hung = true;
        ::kill(worker.pid, SIGKILL);
        break;
      }
      char chunk[4096];
      const ssize_t n = ::read(worker.control, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;  // the worker closed its end: it has exited or died
      buffer.append(chunk, size_t(n));
      for (size_t eol; (eol = buffer.find('\n')) != std::string::npos; buffer.erase(0, eol + 1))
        handle(buffer.substr(0, eol), run);
    }
    ::close(worker.control);
    ::close(worker.ack);
    while (::waitpid(worker.pid, &run.status, 0) < 0 && errno == EINTR) {
    }
    return run;
  }

  void handle(const std::string& line, WorkerRun& run) {
    std::istringstream in(line);
    std::string event;
    size_t archive = 0, object = 0;
    in >> event >> archive;
    if (event == "ready") {
      run.ready = true;
      unresolved_ = archive;  // the number after "ready"
    } else if (event == "archive" && archive < totals_.size()) {
      in >> totals_[archive].objects;
    } else if (event == "begin" && in >> object) {
      std::string what;
      std::getline(in >> std::ws, what);
      run.pending = what;
      run.resume = {archive, object + 1};
    } else if (event == "end" && in >> object) {
      std::string verdict;
      size_t pipelines = 0, feedback = 0, hits = 0;
      int64_t time = 0, driver = 0;
      in >> verdict >> pipelines >> time >> driver >> feedback >> hits;
      if (verdict == "ok" && archive < totals_.size()) {
        ++totals_[archive].ok;
        totals_[archive].add(pipelines, time, driver, feedback, hits);
      }
      run.pending.reset();
      run.progressed = true;
      run.resume = {archive, object + 1};
    } else if (event == "done" && archive < totals_.size()) {
      out_ << printable(options_.archives[archive].string()) << ": " << totals_[archive].summary() << '\n';
      out_.flush();  // before the worker's next line, which waits for this byte
      const char byte = 1;
      while (::send(run.ack, &byte, 1, MSG_NOSIGNAL) < 0 && errno == EINTR) {
      }
      run.progressed = true;
      run.resume = {archive + 1, 0};
    }
  }

  const VerifyOptions& options_;
  std::ostream& out_;
  std::ostream& err_;
  std::vector<VerifyTotals> totals_;  // per archive
  size_t unresolved_ = 0;             // variants no archive has
  int exit_code_ = kExitSuccess;
};

}  // namespace

int supervise_verify(const VerifyOptions& options, std::ostream& out, std::ostream& err) {
  return Supervisor(options, out, err).run();
}

}  // namespace statepack::packager
