// A repack that changed nothing: the archive the last pack of the same inputs made, taken from the
// compile cache instead of compiling, laying out, encoding and checking it all again (issue 39: a warm
// pack of 1,000 small shaders cost 7 % of a cold one, of 1,000 real-sized ones 13 %; the archive alone is
// tens of megabytes to encode and check).
//
// The record's key covers everything that decides the archive except #includes: statepack's code
// (code_identity: glslang, SPIRV-Tools and the rest by build ID), the options that decide the bytes, every
// notation file read (by the name it was read under and a SHA-256 of its text), and every shader's compile
// key (its file's name and text, macros, stage, entry point, environment). The record lists every #include
// the pack's compiles asked for; a pack that finds the record re-resolves and re-reads each of them (as a
// compile entry's hit does), and only when all still hold writes the recorded archive: the bytes of the
// pack that made it, so byte-identical to a clean pack. Anything else is a normal pack, which records
// its archive again.
//
// A project (where the pack runs, the notation files it is given, its options: what names its bundle in
// compile_cache.hpp) has one record, replaced by each pack that makes an archive, so a cache holds one
// archive per project, not one per edit. The entry's key names the project; its payload:
//
// | payload bytes | meaning                                                                       |
// |---------------|-------------------------------------------------------------------------------|
// | 0..3          | u32 record version (2)                                                        |
// | 4..35         | the key of the inputs it was made from (above): another is a miss             |
// | 36..39        | u32 count of #include records, then each as compile entries keep them         |
// |               | (compile_cache.hpp: header, includer, local, path, text hash)                 |
// | then          | u64 archive size (low, high u32), zeros to a multiple of 16 bytes (the        |
// |               | archive is read in place: decode needs it aligned), then the archive's bytes  |
//
// Only a pack that printed nothing (no warning, no note) is recorded, and only one whose notation read
// without a message reuses one, so a reuse prints what the pack it replaces would have. Not with
// --dump-dir or --shard (they do more than write the archive), nor for notation held in memory.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "pack/input_stamps.hpp"
#include "pack/packer.hpp"
#include "shaders/compile_cache.hpp"

namespace statepack::packager {

class RepackMemo;

struct ArchiveKey {
  CacheKey slot{};                      // the project's record
  CacheKey inputs{};                    // what the archive was made from
  CacheKey setup{};                     // statepack's code and the options (setup_key)
  std::vector<InputFile> shader_files;  // read to make the key: the depfile's and the output checks'
  // Each shader file's text as the key read and hashed it, by the path a compile lists it under: the
  // compile-cache lookups take it instead of reading the file again, and a file saved between the key and
  // a compile made another archive than the key says, and is not recorded.
  std::map<std::filesystem::path, CompileCache::KnownText> shader_texts;
};

// Where the project named `project` keeps its archive record (ArchiveKey::slot).
CacheKey archive_slot(std::string_view project);
// statepack's code and the options that decide the archive's bytes: the part of the inputs key known
// before anything is read (input_stamps.hpp).
CacheKey setup_key(const PackOptions& options);

// The key of this pack's archive record; nullopt when the pack has none (see above), a shader file
// cannot be read (the compile reports why), or one read twice (two shaders of it) changed in between.
// `project`: the text that names the pack's project.
// `memo`: a --watch session's memory of its last pack, whose shader texts that still hold are not read
// again (repack_memo.hpp).
std::optional<ArchiveKey> archive_key(const PackOptions& options, std::string_view project,
                                      const Notation& notation, const Diagnostics& diagnostics,
                                      const RepackMemo* memo = nullptr);

// The archive recorded under `key` when every #include the record lists still holds; `files_read` gets
// the shader files and the #includes. Its bytes are the cache file's, mapped, valid while `holder` lives.
struct RecordedArchive {
  std::shared_ptr<const void> holder;
  std::span<const uint8_t> bytes;
  CacheKey id{};  // record_id: what input stamps vouch for
};
// A record's identity: a SHA-256 of its payload before the archive (version, inputs key, every #include
// with its text's hash, the archive's size, padding).
CacheKey record_id(std::span<const uint8_t> header);
std::optional<RecordedArchive> find_archive(CompileCache& cache, const ArchiveKey& key,
                                            const CompileOptions& options,
                                            std::vector<InputFile>& files_read);
// The same without reading the notation or any shader: when the project's input stamps
// (input_stamps.hpp) still hold, each #include the record lists is found where it was, and the record is
// the one the stamps vouch for. `files_read` gets every file the stamps list.
std::optional<RecordedArchive> find_unchanged_archive(CompileCache& cache, const PackOptions& options,
                                                      std::string_view project,
                                                      std::vector<InputFile>& files_read);

// Records `archive` under `key` with the #includes of `compiles`, written now (after the pack's own flush);
// a warning, or "" when written (or left out: a shader file whose compiled text is not the one the key
// hashed). Never over one of `inputs`. Then writes `stamps`, taken of `inputs` (input_stamps.hpp), with
// the tables hint, as the record's stamps (none when nullopt).
std::string record_archive(CompileCache& cache, const ArchiveKey& key,
                           const std::vector<const CompiledShader*>& compiles,
                           std::span<const uint8_t> archive, const std::vector<InputFile>& inputs,
                           const std::optional<TakenStamps>& stamps, const std::optional<TablesHint>& tables);

}  // namespace statepack::packager
