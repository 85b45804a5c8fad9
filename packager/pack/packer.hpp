// The pack command: notation in, archive out.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "notation/diagnostics.hpp"
#include "notation/notation.hpp"
#include "shaders/remote_cache.hpp"
#include "shaders/shader_compiler.hpp"

namespace statepack::packager {

// Exit codes of the CLI (docs/cli.md).
enum ExitCode : int { kExitSuccess = 0, kExitInputError = 1, kExitUsage = 2, kExitIoError = 3 };

// The exit code of a failed output (OutputSet, write_file_atomically): a path that may not be an output
// is the caller's usage error, anything else an I/O error. Chosen by the code, never by the message.
inline int exit_code_of_output_error(const Error& error) {
  return error.code == ErrorCode::invalid_argument ? kExitUsage : kExitIoError;
}

struct PackOptions {
  std::vector<std::filesystem::path> inputs;
  NotationOptions notation;
  CompileOptions compile;
  std::filesystem::path output;
  std::optional<std::filesystem::path> depfile;
  std::optional<std::filesystem::path> dump_dir;  // SPIR-V and disassembly per pipeline and shader
  uint32_t content_version = 0;
  bool vulkan = true;    // --vulkan: the Vulkan backend
  bool opengl = false;   // --opengl: the OpenGL backend (OpenGL 4.5 + ARB_gl_spirv, docs/cli.md)
  uint32_t threads = 0;  // 0: all cores
  bool print_contents = false;
  bool check_only = false;
  bool time_report = false;  // --time-report: each stage's wall time to `err`
  // --strict: what Diligent only warns about (ResourceLayout variables and immutable samplers that name
  // nothing the shaders use) is an error.
  bool strict = false;
  // --cache-dir: compiled and finalised SPIR-V kept between runs (compile_cache.hpp); its size bound.
  std::optional<std::filesystem::path> cache_dir;
  uint64_t cache_max_bytes = uint64_t(1) << 30;
  // With a cache: an unchanged pack writes the archive the last pack of its project recorded there
  // (pack/archive_reuse.hpp); --no-archive-reuse: neither read nor write that record.
  bool archive_reuse = true;
  // --remote-cache (or STATEPACK_REMOTE_CACHE): servers behind the cache (remote_cache.hpp); without
  // --cache-dir the pack keeps what it reads from them in memory only.
  std::vector<RemoteSpec> remote_cache;
  // STATEPACK_CACHE_KEY or the file STATEPACK_CACHE_KEY_FILE names: the team's key that signs every
  // entry written and must sign every entry read (compile_cache.hpp).
  std::vector<uint8_t> cache_signing_key;
  // --shard K/N (1 <= K <= N): compile only the shaders whose compile key falls in shard K, into the
  // caches; lay out nothing, write no archive. 0/0: no sharding.
  uint32_t shard = 0, shards = 0;
  size_t max_errors =
      Diagnostics::kDefaultMaxErrors;  // 0: no limit  // --check: pack and validate everything, write nothing
};

class CompileCache;

// What one pack of several (pack --watch) shares with the others and leaves for the next.
class RepackMemo;

struct PackSession {
  // In: the compile cache to use instead of opening --cache-dir (a cache kept between packs).
  CompileCache* cache = nullptr;
  // In and out: what the last pack read and made, for this one to take what still holds instead of
  // reading, looking up and compiling it again; replaced by what this pack made when it writes its
  // archive (repack_memo.hpp). nullptr: none.
  RepackMemo* memo = nullptr;
  // Out: every file the pack read, as the depfile lists them: notation files, their imports, shaders and
  // #includes. Filled also when the pack fails, with what it managed to read (absent files are not in
  // it), so that a fix of the file with the error is seen.
  std::vector<std::filesystem::path> files_read;
};

// A pack whose inputs all stat as the project's input stamps say (pack/input_stamps.hpp): the recorded
// archive written without reading any input; its ExitCode. nullopt, having printed nothing, when the
// stamps do not hold (or cannot: no --cache-dir, --no-archive-reuse, --dump-dir, --shard): run_pack then.
std::optional<int> pack_if_unchanged(const PackOptions& options, std::ostream& out, std::ostream& err);

// Runs a whole pack; returns an ExitCode. Diagnostics are printed to `err`, progress to `out`. A pack
// that fails writes nothing: an archive already at --output is left as it was.
int run_pack(const PackOptions& options, std::ostream& out, std::ostream& err,
             PackSession* session = nullptr);

}  // namespace statepack::packager
