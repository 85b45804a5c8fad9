// The decoded tables of a loaded Archive, for the dearchiver itself and statepack's own tests: the
// public API keeps them private (format::Contents is the internal model, free to change).
#pragma once

#include "format/archive_format.hpp"
#include "format/spirv_walk.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::detail {

// Exported although internal: statepack_gl, a library of its own, reads an Archive's tables through it.
struct STATEPACK_API ArchiveAccess {
  static const format::Contents& contents(const Archive& archive);
  // A blob as the load's checks walked it (every blob a shader uses); null beyond the blobs.
  static const spirv::Module* walked(const Archive& archive, uint32_t blob);
};

}  // namespace statepack::detail
