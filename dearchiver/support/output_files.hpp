// Writing outputs (archives, depfiles, dumps, pipeline caches, images) all or nothing, without ever replacing
// an input or following a planted link.
//
// Every output is first written in full to a temporary beside it (an unnamed O_TMPFILE where the file
// system has them, so a killed run leaves nothing behind; else a new file created with O_EXCL, which
// never follows a symlink). Only when every output of the run has been written are they renamed over
// their destinations, so an unwritable depfile can no longer leave a new archive with an old depfile.
// Temporaries of killed runs are named ".NAME.statepack-tmp-PID-N" and removed by the next run that
// writes NAME, once no process PID is alive.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "file_io.hpp"
#include "statepack/result.hpp"

namespace statepack::detail {

// A file a run read, by path (for messages) and identity (so that no output replaces it).
struct InputFile {
  std::filesystem::path path;
  FileIdentity identity;
};

class OutputSet {
 public:
  explicit OutputSet(std::vector<InputFile> inputs) : inputs_(std::move(inputs)) {}
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet();  // removes temporaries that were not committed

  // Why `path` cannot be an output of this run, or an empty string: it is a symbolic link, a directory,
  // a device or any other non-regular file, one of the run's inputs (by identity: the same path, a `..`
  // spelling, a symlink or a hard link all count), or another output of the run.
  std::string refuse_reason(const std::filesystem::path& path) const;

  // Checks `path`, then writes `bytes` to a temporary beside it. A path refuse_reason refuses is an
  // `invalid_argument` error (the caller's choice of output: a usage error), every other failure
  // `io_error`; the message says which path and why. Callers choose exit codes by the code, never by
  // the text.
  Result<void> stage(const std::filesystem::path& path, std::span<const uint8_t> bytes);

  // Renames every staged temporary over its destination; `io_error` when one cannot be.
  Result<void> commit();

 private:
  struct Staged {
    std::filesystem::path path;
    int fd = -1;                 // the O_TMPFILE, until it is linked
    std::filesystem::path temp;  // its name once it has one
  };
  std::vector<InputFile> inputs_;
  std::vector<Staged> staged_;
};

}  // namespace statepack::detail
