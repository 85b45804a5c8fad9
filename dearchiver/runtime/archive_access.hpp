// The decoded tables of a loaded Archive, for the dearchiver itself and statepack's own tests: the
// public API keeps them private (format::Contents is the internal model, free to change).
#pragma once

#include "format/archive_format.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::detail {

struct ArchiveAccess {
  static const format::Contents& contents(const Archive& archive);
};

}  // namespace statepack::detail
