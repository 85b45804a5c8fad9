// Input stamps: a repack whose inputs have not changed writes the recorded archive (archive_reuse.hpp)
// without reading them. Finding the record by its key means reading and hashing every notation and
// shader file (for 1,000 small shaders ~40 ms, more than half of such a repack); a stamp says what stat
// said of each file when its bytes were the ones the record was made from, and a file that stats the
// same is taken to hold the same bytes, as git's index and make take it.
//
// A stamp is the device, inode, size, modification and change times (ns) of a file. The change time is
// set by the kernel on every write, rename or metadata change, and no tool can set it back. A file
// stamped within kRacyWindow of the pack that read it is not trusted (git's "racily clean"): a file
// system's timestamps are coarse (a clock tick), so a second write in the same tick could keep every
// field. Such stamps are written all the same, counted unsettled, and vouch for nothing: the next pack
// reads everything and stamps again, but still finds the tables hint below (an edit loop packs within
// seconds of each edit, so every pack after an edit is such a pack). Besides its
// files, a notation's result depends on where each file name was found (resolve_file: next to the
// notation, then the -r or -s directories): each lookup is stamped by what it found and done again, so a
// file that appears earlier in the search misses. #includes are looked up again from the record.
//
// The stamps of a project are one cache entry of its own (local, like the record), next to the record's:
//
// | payload bytes | meaning                                                                        |
// |---------------|--------------------------------------------------------------------------------|
// | 0..3          | u32 stamps version (4)                                                         |
// | 4..35         | the record these stamps vouch for: a SHA-256 of its payload before the archive |
// |               | (its inputs key and #includes with their texts' hashes: archive_reuse.hpp)     |
// | 36..67        | setup key: statepack's code and the options that decide the archive's bytes   |
// | 68..71        | u32 count of files stat'ed within the racy window: unless 0, the stamps vouch  |
// |               | for nothing (the hint alone is used)                                           |
// | 72..75        | u32 1 when a tables hint follows (else 0): u32 source language (SourceLanguage), |
// |               | u32 stage (VkShaderStageFlagBits), u32 GLSLVersion, the #version line (string) |
// | then          | u32 count of lookups, then each: u32 kind (0 -r, 1 -s), name, base directory,  |
// |               | found path (strings: u32 length, bytes)                                        |
// | then          | u32 count of files, then each: path, u32 1 when the pack read it (0: a name a  |
// |               | lookup found, stamped through a link), u64 device, inode, size, modification   |
// |               | time (u64 seconds, u64 nanoseconds), change time (the same)                    |
//
// A pack with a cache, archive reuse on, no --dump-dir or --shard and notation from files looks for its
// stamps before anything else; any difference (a file, a lookup, the options, the record) is a normal
// pack, which stamps again when it records an archive or reuses one.
//
// The tables hint: what picks glslang's built-in tables (compiler_warmup.hpp) for the project's first
// shader: its language and #version. A repack that finds a stamped file changed (or unsettled) starts
// building them from the hint as it starts, before it has read its notation; a wrong hint costs only
// that work.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "notation/notation.hpp"
#include "shaders/compile_cache.hpp"

namespace statepack::packager {

// A file's stamp stats within this long of (or after) the start of the pack that read it are not trusted:
// longer than a clock tick, and than FAT's two-second modification times.
inline constexpr std::chrono::seconds kRacyWindow{2};

struct FileStamp {
  uint64_t device = 0, inode = 0, size = 0;
  std::pair<int64_t, int64_t> modified, changed;  // seconds and nanoseconds since the epoch
  bool operator==(const FileStamp&) const = default;
};
// stat(2) of `path` (a link followed, as a read follows it); nullopt when it cannot be taken.
std::optional<FileStamp> stamp_of(const std::filesystem::path& path);
std::optional<FileStamp> stamp_of(const std::string& path);

// What a pack that began at `started` may trust of a stamp taken after it read the file: a file changed
// within kRacyWindow before (or after) that is not trusted.
class RacyWindow {
 public:
  explicit RacyWindow(std::chrono::system_clock::time_point started);
  bool trusts(const FileStamp& stamp) const { return stamp.modified < before_ && stamp.changed < before_; }

 private:
  std::pair<int64_t, int64_t> before_;  // seconds and nanoseconds since the epoch
};

// Whether the search of `lookup` (next to its base, then the -r or -s directories by its kind) still finds
// what it found.
bool lookup_finds_the_same(const FileLookup& lookup, const NotationOptions& options);

// Where the stamps of the record at `record_slot` are kept.
CacheKey stamps_slot(const CacheKey& record_slot);

// What picks glslang's built-in tables for a shader like the project's first (the stamps' tables hint).
struct TablesHint {
  SourceLanguage language = SourceLanguage::glsl;
  uint32_t stage = 0;         // VkShaderStageFlagBits
  uint32_t glsl_version = 0;  // GLSLVersion
  std::string version_line;   // its #version line, or ""
  bool operator==(const TablesHint&) const = default;
};

// What a set of stamps vouches for.
struct StampedInputs {
  CacheKey record{};  // record_id of the record they vouch for
  CacheKey setup{};
  std::vector<FileLookup> lookups;
  std::vector<InputFile> files;
  std::optional<TablesHint> tables;
};

// Stamps `stamped.files` for the record at `record_slot`, counting those changed within kRacyWindow before
// `started` (when the pack began reading), or after it, as unsettled; unless one cannot be stat'ed or is
// no longer the file the pack read (its device and inode then): then nothing is written and "" returned.
// Returns a warning when the cache cannot write. The same as take_input_stamps then store_input_stamps.
std::string write_input_stamps(CompileCache& cache, const CacheKey& record_slot, const StampedInputs& stamped,
                               std::chrono::system_clock::time_point started);

// The stamps of what a pack read, without what they vouch for: taken as soon as the pack has read its last
// input, on another core while it makes the archive (a stat is as good then as after: whatever changes
// after `started` is unsettled). nullopt where write_input_stamps writes nothing.
struct TakenStamps {
  std::vector<uint8_t> body;  // the lookups and the files, as the table above lays them out
  uint32_t unsettled = 0;
};
std::optional<TakenStamps> take_input_stamps(const std::vector<FileLookup>& lookups,
                                             const std::vector<InputFile>& files,
                                             std::chrono::system_clock::time_point started);
// Writes `taken` as the stamps of the record `stamped.record` (with its setup key and tables hint); a
// warning, or "".
std::string store_input_stamps(CompileCache& cache, const CacheKey& record_slot, const StampedInputs& stamped,
                               const TakenStamps& taken);

std::optional<StampedInputs> unchanged_inputs(CompileCache& cache, const CacheKey& record_slot,
                                              const CacheKey& setup, const NotationOptions& options);

// The tables hint of `stamps` (a stamps entry's payload), read from its head only; nullopt when none.
std::optional<TablesHint> stamped_hint(std::span<const uint8_t> stamps);
// The same, when one of its files no longer stats as stamped or was unsettled (a compile is then likely);
// nullopt when none, or when every file does.
std::optional<TablesHint> hint_if_changed(std::span<const uint8_t> stamps);

}  // namespace statepack::packager
