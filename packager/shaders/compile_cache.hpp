// statepack pack --cache-dir: compiled and finalised SPIR-V kept between runs, so an unchanged shader
// is never compiled (or optimised and validated) again. An entry is found by a SHA-256 of everything that
// decides its result (a shared cache is written by other machines: no two inputs may be made to share a
// key):
//
// - a compile: statepack's own code (glslang and SPIRV-Tools are linked into it: the build IDs of its
//   loaded objects), the options (target, -D macros, -s directories, --max-input-size), the shader's
//   stage, language, entry point, macros, file name and text. No path enters as it lies on this machine:
//   a file and an -s directory enter by the name glslang is given (display_path: relative to the working
//   directory when below it), so two checkouts at different paths share entries. Its #includes are not
//   in the key: the entry lists each one glslang asked for (the name, who included it, where it was found
//   (by the same kind of name), a SHA-256 of its text), and a hit re-resolves and re-reads every one of
//   them. Same text and same includes found in the same files with the same text give the same
//   preprocessed source, so the same SPIR-V (an include that now resolves elsewhere, or changed, is a miss).
// - a finalisation (optimise, strip, validate): the code, the options and the module's words.
//
// Entries are files DIR/v2/XX/<64 hex digits> (XX: the first two), each written to a temporary beside it
// and renamed, so two packs sharing the directory at once only ever see whole entries; each holds a
// SHA-256 of its payload, so a truncated or damaged one is a miss and is written again. Only successful
// results are kept. The directory is kept under a size bound: a pack that writes entries trims the
// cache to it, the least recently used first (a hit marks an entry used), never removing what it wrote
// or read itself (the directories are listed only when the size the last pack left in DIR/v2/size, plus
// what this one wrote, passes the bound); `statepack cache prune` trims on demand. The archive is
// byte-identical with and without a cache. (DIR/v1 holds 0.4's entries, XXH3-keyed; never read.)
//
// | entry bytes | meaning                                                                          |
// |-------------|----------------------------------------------------------------------------------|
// | 0..3        | "SPKC"                                                                           |
// | 4..7        | u32 entry layout version (2)                                                     |
// | 8..39       | the 256-bit key (the file's name, repeated: an entry under another name is not   |
// |             | a hit)                                                                           |
// | 40..47      | u64 payload size                                                                 |
// | 48..79      | SHA-256 of the payload                                                           |
// | 80..111     | with a team key: HMAC-SHA-256 under it of bytes 8..39 and 48..79; else zeros     |
// | 112..       | payload: a compile's (u32 backend-specific flag; u32 count and per #include str  |
// |             | header, str includer, u8 local, str path, 32-byte text hash; u32 count and strs  |
// |             | of combined image samplers; u32 count and (u32 variable, str semantic) of vertex |
// |             | inputs; str entry point; u32 count and SPIR-V words; with flag 2, the module's   |
// |             | Reflection, field by field as spirv_reflect.hpp declares them) or a              |
// |             | finalisation's (u32 count and SPIR-V words). str: u32 length and bytes; all      |
// |             | little-endian.                                                                   |
//
// The same entry bytes go to and come from the servers of --remote-cache (remote_cache.hpp), behind the
// local directory: a local miss asks them, and what they return is checked as a local entry is (key,
// size, hash, signature) and, unless signed with the team's key, a finalised module is validated as a
// fresh one is; then it is used and kept locally. What a pack makes is written to both.
//
// A pack's bundle: one more entry, under a key made of the project (the working directory, the notation
// files given, the options that decide entries; not the output) instead of a shader, whose payload is
// every small entry (16 KiB at most) a recent pack of that project used, each as (32-byte key, u64 size,
// payload). A pack maps it first and finds its entries there before it opens an entry file: a warm pack
// of N small shaders opens one file instead of 2N (a large entry is worth its own file's opening, and
// would make the bundle costly to rewrite). A bundle entry serves only under its own key, so a bundle
// that another project wrote, or one that is stale, costs its read and nothing else. A pack writes a new
// one when what it used differs enough from what the bundle holds: a name in it written again, or more
// than 1/32 of the entries used read or written beside it plus held unused (so that one changed shader
// of a thousand does not rewrite the whole bundle). It is trimmed like any entry; it stays
// local (never sent to a server).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cache_payload.hpp"
#include "digest.hpp"
#include "notation/input_file.hpp"
#include "shader_compiler.hpp"
#include "spirv_reflect.hpp"

namespace statepack::packager {

using CacheKey = Digest;
class RemoteCache;

class CompileCache {
 public:
  static constexpr uint64_t kDefaultMaxBytes = uint64_t(1) << 30;

  // Opens (creating it if needed) a cache directory; nullopt with `error` set when it cannot be used.
  static std::optional<CompileCache> open(const std::filesystem::path& dir, uint64_t max_bytes,
                                          std::string& error);
  // A cache in memory, for the packs of one process (pack --watch without --cache-dir): the same
  // entries, found the same way (#includes re-read and compared on a hit), kept in a map instead of
  // files under the same kind of size bound. flush() only moves what was kept into the map.
  static CompileCache in_memory(uint64_t max_bytes);
  CompileCache(CompileCache&&) noexcept;
  ~CompileCache();

  // A compile from the cache, when every input it depended on is unchanged, with the module's reflection
  // when it was kept too; else nullopt. Thread-safe.
  struct Compile {
    CompiledShader compiled;
    std::optional<Reflection> reflection;
  };
  // `known`: the shader file's text as this pack already read and hashed it (ArchiveKey), so that it is
  // not read again; nullptr: read here.
  struct KnownText {
    InputFile file;
    Digest hash{};
  };
  std::optional<Compile> find_compile(const ShaderDesc& shader, const CompileOptions& options,
                                      const KnownText* known = nullptr);
  // Keeps a successful compile and, when given, its reflection (written by flush()). Thread-safe.
  void keep_compile(const ShaderDesc& shader, const CompileOptions& options, const CompiledShader& compiled,
                    const Reflection* reflection);
  // The same for finalize_spirv: `input` before, `output` after.
  std::optional<std::vector<uint32_t>> find_finalized(const std::vector<uint32_t>& input,
                                                      const CompileOptions& options);
  void keep_finalized(const std::vector<uint32_t>& input, const CompileOptions& options,
                      const std::vector<uint32_t>& output);

  // A whole pack's record (pack/archive_reuse.hpp) under its own key: from this cache only, never from
  // or to a server (an archive is one build's product, not a compile a team shares), and counted in no
  // hit or miss. find_local is thread-safe.
  // Its payload is mapped (records are archives, tens of megabytes), valid while `holder` lives.
  struct LocalEntry {
    std::shared_ptr<const void> holder;
    std::span<const uint8_t> payload;
  };
  std::optional<LocalEntry> find_local(const CacheKey& key);
  // When the entry under `key` in the cache directory was last written (or used: the cache's LRU touches
  // what a pack uses); nullopt when it has none.
  std::optional<std::filesystem::file_time_type> local_time(const CacheKey& key) const;
  // Writes the record now (`payload` then `payload_tail`: an archive is not copied into one buffer), once
  // the pack's flush is done: the archive exists only after it. Returns a warning, "" when written.
  std::string store_local(const CacheKey& key, std::span<const uint8_t> payload,
                          std::span<const uint8_t> payload_tail, const std::vector<InputFile>& inputs);
  // Reads the bundle of `project` (a text naming the pack: directory, inputs, output), so that the
  // entries the last pack of it used are found without opening their files; flush() writes the bundle
  // again when this pack used others. Call before the first find_*.
  void use_bundle(std::string_view project);

  // Servers behind this cache (--remote-cache): asked after a local miss; what they return is checked
  // as a local entry is, used, and kept locally; what this pack compiles is written to them by flush().
  void use_remote(std::shared_ptr<RemoteCache> remote) { remote_ = std::move(remote); }
  // A team's key (STATEPACK_CACHE_KEY or its file): every entry written is signed with it, and an entry
  // read (local or remote) that is not signed with it is not used.
  void set_signing_key(std::vector<uint8_t> secret) { secret_ = std::move(secret); }

  // An entry under `key` that a pack took from elsewhere instead of a find_* hit (a --watch session's
  // memory of its last pack: pack/repack_memo.hpp): counted as used as the hit would have been, so that
  // trimming keeps it and the bundle goes on holding it. Thread-safe.
  void note_used(const CacheKey& key);

  // Writes what was kept, never over one of `inputs` (by identity) or through a link, then (when it
  // wrote anything) trims the cache to the size bound. Returns a warning ("" when all went well): a
  // cache that cannot be written costs time, not correctness.
  std::string flush(const std::vector<InputFile>& inputs);

  struct Stats {
    size_t hits = 0, misses = 0, damaged = 0, written = 0, removed = 0;
    size_t from_bundle = 0;     // of the entries read, those found in the pack's bundle
    size_t remote_hits = 0;     // entries a remote server had (after a local miss), checked and used
    size_t remote_refused = 0;  // entries a remote server returned that failed their check: not used
  };
  // Why the first entry a server returned was refused ("" when none was).
  std::string first_refusal() const;
  Stats stats() const;

  // `statepack cache prune`: removes the least recently used entries until the cache holds at most
  // `max_bytes`, and temporaries of runs that died. Returns what it removed, or an error.
  struct PruneResult {
    uint64_t bytes_before = 0, bytes_after = 0;
    size_t entries_before = 0, entries_after = 0;
    std::string error;
  };
  static PruneResult prune(const std::filesystem::path& dir, uint64_t max_bytes);

  // `statepack cache export`/`import`: a cache's entries as one file, to move them between machines as a
  // build artifact (no shared server). The file: "SPKX", u32 version 1, then per entry u64 size and the
  // entry's bytes as its file holds them (header with key, payload hash and signature). Import checks each
  // entry as a read does (and its signature when `secret` is given) and writes the good ones.
  struct TransferResult {
    size_t entries = 0, present = 0, refused = 0;
    uint64_t bytes = 0;
    std::string error;
    int exit_code = 2;  // with an error: 1 a damaged export, 2 a usage error, 3 an I/O error
  };
  static TransferResult export_entries(const std::filesystem::path& dir, const std::filesystem::path& file);
  static TransferResult import_entries(const std::filesystem::path& dir, const std::filesystem::path& file,
                                       std::span<const uint8_t> secret);

 private:
  CompileCache(std::filesystem::path dir, uint64_t max_bytes);
  struct Pending {
    CacheKey key;
    std::vector<uint8_t> payload;
    bool to_remote = true;  // made by this pack (a remote's own entry is only kept locally)
  };
  // A check of a payload from a remote server beyond its entry's (why it is refused, or "").
  using PayloadCheck = std::function<std::string(std::span<const uint8_t>)>;
  std::optional<std::vector<uint8_t>> read_entry(const CacheKey& key, const PayloadCheck& check = {});
  std::optional<std::vector<uint8_t>> read_local(const CacheKey& key, const std::string& name);
  void write_to_remote(const std::vector<Pending>& pending);
  void keep(const CacheKey& key, std::vector<uint8_t> payload);
  // Writes one entry file atomically; false with `warning` set when it could not.
  // (`payload_tail`: more payload after `payload`, hashed and written as if one.)
  bool write_entry(const CacheKey& key, std::span<const uint8_t> payload,
                   const std::set<FileIdentity>& inputs, std::string& warning,
                   std::span<const uint8_t> payload_tail = {});
  void trim_to_bound(std::set<std::string> keep);
  // The bundle this pack used, rewritten when it used other entries; its name, or "".
  std::string write_bundle(const std::vector<Pending>& written, const std::set<FileIdentity>& inputs,
                           std::string& warning);

  std::string flush_to_memory();

  std::filesystem::path dir_;  // DIR/v2; empty for a cache in memory
  uint64_t max_bytes_;
  mutable std::mutex mutex_;  // pending_, used_, memory_, use_clock_, the remote's counts
  std::vector<Pending> pending_;
  std::set<std::string> used_;     // entries this run read: kept when it trims the cache
  std::set<std::string> flushed_;  // entries the last flush wrote: kept when a record's write trims it
  std::atomic<size_t> hits_{0}, misses_{0}, damaged_{0};
  size_t written_ = 0, removed_ = 0;
  // A cache in memory: its entries by name, each with the payload and when it was last used.
  struct MemoryEntry {
    std::vector<uint8_t> payload;
    uint64_t last_used = 0;
  };
  std::map<std::string, MemoryEntry> memory_;
  uint64_t memory_bytes_ = 0, use_clock_ = 0;
  // The pack's bundle: its key, its file, and the entries in it by name; the payloads this pack read
  // from entry files (for the next bundle).
  std::optional<CacheKey> bundle_key_;
  std::shared_ptr<const uint8_t> bundle_map_;  // the bundle file, mapped
  std::map<std::string, std::span<const uint8_t>, std::less<>> bundle_;
  std::map<std::string, std::vector<uint8_t>> read_from_files_;
  std::atomic<size_t> from_bundle_{0};
  int64_t growth_ = 0;  // bytes this pack's writes added to the cache (less what they replaced)
  std::set<std::string> checked_subdirectories_;  // during a flush: those found to be real directories
  std::shared_ptr<RemoteCache> remote_;
  std::vector<uint8_t> secret_;
  size_t remote_hits_ = 0, remote_refused_ = 0;  // (under mutex_)
  std::string first_refusal_;
};

// The code that decides a result: statepack's own and every shared library it runs with, by build ID.
const CacheKey& code_identity();

// #include records as compile entries and archive records keep them: (header, includer, local, where it
// was found by the name glslang gives it, SHA-256 of its text). read_include_record: false when the
// payload ends early.
void write_include_record(PayloadWriter& w, const IncludeRecord& rec);
bool read_include_record(PayloadReader& r, IncludeRecord& rec);
// An #include's text as a check read it, by the name glslang gives its file (to check several records
// that name one file with one read).
struct IncludeText {
  Digest hash{};
  uint64_t size = 0;
  InputFile file;
};
using IncludeTexts = std::map<std::string, IncludeText>;
// Where `rec`'s header is found now, when that is where it was found (rec.path); nullopt otherwise.
std::optional<std::filesystem::path> include_found_again(const IncludeRecord& rec,
                                                         const CompileOptions& options);
// The file of `rec` when it still holds (the header resolves to the same file, whose text is the same)
// and the text sizes counted in `included` stay within --max-input-size; else nullopt.
std::optional<InputFile> include_still_holds(const IncludeRecord& rec, const CompileOptions& options,
                                             uint64_t& included, IncludeTexts* texts = nullptr);

// The key of a shader's compile (its file read and hashed), for --shard; nullopt when its file cannot be
// read (the compile reports why).
// `file`, when given, is set to the shader file as read (unchanged for an inline Source); `text`, when
// given, to the SHA-256 of the text hashed (CompiledShader::source_hash of a compile of it).
std::optional<CacheKey> compile_cache_key(const ShaderDesc& shader, const CompileOptions& options,
                                          InputFile* file = nullptr, Digest* text = nullptr);
// The same from a text already read and hashed (`known`: the shader file's, as its path and identity).
CacheKey compile_cache_key(const ShaderDesc& shader, const CompileOptions& options,
                           const CompileCache::KnownText& known);
// The keys find_compile (of a source whose text hashes to `source_hash`) and find_finalized look up.
CacheKey compile_entry_key(const ShaderDesc& shader, const CompileOptions& options,
                           const Digest& source_hash);
CacheKey finalized_entry_key(const std::vector<uint32_t>& input, const CompileOptions& options);

}  // namespace statepack::packager
