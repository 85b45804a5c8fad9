// statepack pack --watch: pack, then pack again whenever a file the pack read changes (docs/cli.md,
// "Development loop").
#pragma once

#include <cstdint>
#include <iosfwd>

#include "pack/packer.hpp"

namespace statepack::packager {

struct WatchOptions {
  // How long the inputs must stay unchanged after a change before the repack: a burst of saves (an
  // editor's "save all", a checkout) is one repack.
  uint32_t quiet_ms = 150;
};

// Packs, then stays resident: watches (inotify) the directories of every file the last pack read and
// repacks after a change once `quiet_ms` have passed without another. Each repack prints one line to
// `out`; a failed one prints its errors to `err` and leaves the archive there is. Ends with kExitSuccess
// on SIGINT, SIGTERM or SIGHUP (between packs: a pack under way finishes first, so no temporary is
// left), with kExitUsage when the first pack is refused as a usage error (an output that may never be
// written), with kExitIoError when the watch cannot be set up.
int run_watch(const PackOptions& options, const WatchOptions& watch, std::ostream& out, std::ostream& err);

}  // namespace statepack::packager
