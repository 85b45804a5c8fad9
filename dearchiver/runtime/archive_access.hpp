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
  // Frees the archive's bytes and tables (a reload replaced it and nothing made from it is in use);
  // nothing may read it after.
  static void discard(Archive& archive);
  static bool discarded(const Archive& archive);
  // XXH3-64 of the bytes an archive was read from (0 for one borrowed from memory).
  static uint64_t file_hash(const Archive& archive);
};

// The named objects of an archive other than its pipelines (signatures, render passes, standalone
// shaders), appended in Archive::objects' order: what unpack_all makes besides the pipelines.
void append_other_objects(const format::Contents& contents, std::vector<ObjectInfo>& out);

}  // namespace statepack::detail
