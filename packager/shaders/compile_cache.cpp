#include "compile_cache.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <link.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>
#include <ranges>
#include <set>

#include "cache_payload.hpp"
#include "digest.hpp"
#include "entry_file.hpp"
#include "notation/notation.hpp"
#include "remote_cache.hpp"
#include "shader_environment.hpp"
#include "support/printable.hpp"

namespace statepack::packager {
namespace fs = std::filesystem;
namespace {

constexpr char kMagic[4] = {'S', 'P', 'K', 'C'};
constexpr uint32_t kEntryVersion = 2;
constexpr size_t kHeaderBytes = 112;
constexpr const char* kLayoutDirectory = "v2";            // (v1: 0.4's XXH3 keys, left alone)
constexpr uint64_t kMaxEntryBytes = uint64_t(256) << 20;  // larger than any module statepack writes
constexpr size_t kSubdirectories = 256;
constexpr int64_t kStaleTemporarySeconds = 3600;  // a temporary this old belongs to a run that died
constexpr size_t kMaxBundledPayload = 16 << 10;   // larger entries stay in their own files only
// A bundle is rewritten once the entries a pack used beside it plus those it holds unused pass 1/32 of what
// the pack used (write_bundle).
constexpr size_t kBundleSlack = 32;

// The GNU build ID of a loaded object (a hash the linker computes over the whole file), if it has one.
std::optional<std::string_view> build_id(const dl_phdr_info& info) {
  for (int i = 0; i < info.dlpi_phnum; ++i) {
    const ElfW(Phdr)& p = info.dlpi_phdr[i];
    if (p.p_type != PT_NOTE) continue;
    const auto* at = reinterpret_cast<const uint8_t*>(info.dlpi_addr + p.p_vaddr);
    const uint8_t* end = at + p.p_memsz;
    while (size_t(end - at) >= sizeof(ElfW(Nhdr))) {
      ElfW(Nhdr) note;
      std::memcpy(&note, at, sizeof note);
      const size_t name = (note.n_namesz + 3) & ~size_t(3), desc = (note.n_descsz + 3) & ~size_t(3);
      if (size_t(end - at) - sizeof note < name + desc) break;
      const auto* note_name = at + sizeof note;
      if (note.n_type == NT_GNU_BUILD_ID && note.n_namesz == 4 && std::memcmp(note_name, "GNU", 4) == 0)
        return std::string_view(reinterpret_cast<const char*>(note_name + name), note.n_descsz);
      at += sizeof note + name + desc;
    }
  }
  return std::nullopt;
}

// An entry file mapped, not read (a bundle or an archive record is tens of megabytes; mapped, the page
// cache's pages are used as they are instead of a page fault per page of fresh memory), and marked
// recently used; nullopt when absent, or (counted in `damaged`: written again) not a regular file of an
// entry's size.
struct MappedFile {
  std::shared_ptr<const uint8_t> map;
  size_t size = 0;
};
std::optional<MappedFile> map_entry(const fs::path& path, std::atomic<size_t>& damaged) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (errno != ENOENT) ++damaged;  // a link planted there, or what cannot be read: written again
    return std::nullopt;
  }
  struct stat st {};
  const bool sized = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && uint64_t(st.st_size) >= kHeaderBytes &&
                     uint64_t(st.st_size) <= kMaxEntryBytes;
  void* mapped = sized ? ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0) : MAP_FAILED;
  if (mapped != MAP_FAILED) ::futimens(fd, nullptr);  // recently used: pruned last
  ::close(fd);
  if (mapped == MAP_FAILED) {
    ++damaged;
    return std::nullopt;
  }
  const size_t size = size_t(st.st_size);
  return MappedFile{
      std::shared_ptr<const uint8_t>(static_cast<const uint8_t*>(mapped),
                                     [size](const uint8_t* at) { ::munmap(const_cast<uint8_t*>(at), size); }),
      size};
}

}  // namespace

// The code that decides a result: statepack itself (glslang and SPIRV-Tools are linked into it) and
// every shared library it runs with (spirv-cross reflects, libm folds constants, ...), each by its build
// ID, or by its read-only segments when it has none; so a rebuild of statepack, or an upgrade of a
// library, never reads the entries of another.
const CacheKey& code_identity() {
  static const CacheKey identity = [] {
    KeyBuilder k;
    k.add("statepack compile cache");
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* data) -> int {
          auto& builder = *static_cast<KeyBuilder*>(data);
          const std::string_view name = info->dlpi_name ? info->dlpi_name : "";
          if (name.find("linux-vdso") != std::string_view::npos) return 0;  // the kernel's, not a compiler's
          builder.add(name.substr(name.rfind('/') + 1));
          if (auto id = build_id(*info)) {
            builder.add(*id);
            return 0;
          }
          for (int i = 0; i < info->dlpi_phnum; ++i) {
            const ElfW(Phdr)& p = info->dlpi_phdr[i];
            if (p.p_type != PT_LOAD || (p.p_flags & PF_W)) continue;
            builder.add(
                std::string_view(reinterpret_cast<const char*>(info->dlpi_addr + p.p_vaddr), p.p_filesz));
          }
          return 0;
        },
        &k);
    return k.key();
  }();
  return identity;
}

namespace {

std::string hex(const CacheKey& key) {
  static const char digits[] = "0123456789abcdef";
  std::string out;
  for (uint8_t b : key) out += {digits[b >> 4], digits[b & 15]};
  return out;
}

// The key an entry's name spells (hex() backwards; the name was made by hex()).
CacheKey key_of(std::string_view name) {
  auto digit = [](char c) { return uint8_t(c <= '9' ? c - '0' : c - 'a' + 10); };
  CacheKey key{};
  for (size_t i = 0; i < key.size(); ++i) key[i] = uint8_t(digit(name[2 * i]) << 4 | digit(name[2 * i + 1]));
  return key;
}

// What decides a compile, its #includes aside (they are checked one by one on a hit). No path enters it
// as it lies on this machine: files enter by the name glslang is given (relative to the working directory
// when they lie below it, as the CMake function's packs do), the -s directories likewise; so two checkouts
// at different paths share every entry. (An #include is found again on a hit, wherever the -s directories
// now lie, and must be the same name with the same text.)
CacheKey compile_key(const ShaderDesc& shader, const CompileOptions& options, const Digest& text) {
  KeyBuilder k;
  k.add("compile").add(code_identity());
  k.add(uint64_t(options.vulkan_version)).add(uint64_t(options.opengl)).add(options.max_input_bytes);
  k.add(uint64_t(options.include_dirs.size()));
  for (const auto& d : options.include_dirs) k.add(display_path(d));
  k.add(uint64_t(options.global_macros.size()));
  for (const auto& [name, value] : options.global_macros) k.add(name).add(value);
  k.add(uint64_t(shader.stage)).add(uint64_t(shader.language)).add(shader.entry_point);
  // The environment (definitions, macros, compile flags' pragmas, GLSLExtensions) and the #version a
  // source without one gets: everything glslang reads besides the source and its includes.
  k.add(uint64_t(options.shader_environment));
  const ShaderEnvironment environment = shader_environment(shader, options);
  k.add(environment.preamble).add(uint64_t(environment.default_glsl_version));
  k.add(uint64_t(shader.verbatim)).add(uint64_t(shader.glsl_version));
  if (shader.file.empty())
    k.add(uint64_t(0)).add(shader.name);  // the inline source's name is its file name for glslang
  else
    k.add(uint64_t(1)).add(display_path(shader.file));
  k.add(text);
  return k.key();
}

// The text glslang compiles for a shader: its file's (read as the compile reads it), or its inline Source;
// nullopt when the file cannot be read (the compile reports why).
std::optional<InputText> shader_text(const ShaderDesc& shader, const CompileOptions& options) {
  if (shader.file.empty()) return InputText{shader.source, "", {}};
  InputText input = read_input_file(shader.file, display_path(shader.file), options.max_input_bytes);
  if (!input.error.empty()) return std::nullopt;
  return input;
}

CacheKey finalize_key(const std::vector<uint32_t>& input, const CompileOptions& options) {
  KeyBuilder k;
  k.add("finalize").add(code_identity());
  k.add(uint64_t(options.vulkan_version)).add(uint64_t(options.opengl));
  k.add(uint64_t(options.optimization)).add(uint64_t(options.strip_debug_info));
  k.add(input);
  return k.key();
}

// A module's reflection, field by field (keep it in step with spirv_reflect.hpp: a field left out here
// would come back from the cache as its default).
void write_reflection(PayloadWriter& w, const Reflection& r) {
  w.u32(uint32_t(r.bindings.size()));
  for (const ReflectedBinding& b : r.bindings) {
    w.str(b.name);
    for (uint32_t v : {b.variable, b.block_size, b.set, b.binding, b.descriptor_type, b.count, b.stage,
                       b.set_word, b.binding_word})
      w.u32(v);
    w.str(b.block_layout);
    w.u32(b.combined_attribute ? 1 : 0);
  }
  for (const auto* list : {&r.inputs, &r.outputs}) {
    w.u32(uint32_t(list->size()));
    for (const InterfaceVariable& v : *list) {
      w.str(v.name);
      for (uint32_t x : {v.variable, uint32_t(v.base), v.location, v.component, v.bit_width, v.vector_size,
                         v.columns, v.array_size, uint32_t(v.flat), uint32_t(v.patch)})
        w.u32(x);
    }
  }
  w.u32(uint32_t(r.constants.size()));
  for (const ReflectedConstant& c : r.constants) {
    w.str(c.name);
    for (uint32_t x : {uint32_t(c.kind), c.constant_id, c.size}) w.u32(x);
  }
  w.u32(r.push_constant_size);
  w.str(r.push_constant_name);
  w.str(r.error);
  w.str(r.unsupported);
}

bool read_reflection(PayloadReader& r, Reflection& out) {
  // Each count is checked against the bytes left (an item takes at least that many) before it sizes
  // anything: a damaged count is a miss, not an allocation.
  uint32_t n = 0;
  if (!r.u32(n) || !r.room_for(n, 48)) return false;
  out.bindings.resize(n);
  for (ReflectedBinding& b : out.bindings) {
    uint32_t combined = 0;
    if (!r.str(b.name) || !r.u32(b.variable) || !r.u32(b.block_size) || !r.u32(b.set) || !r.u32(b.binding) ||
        !r.u32(b.descriptor_type) || !r.u32(b.count) || !r.u32(b.stage) || !r.u32(b.set_word) ||
        !r.u32(b.binding_word) || !r.str(b.block_layout) || !r.u32(combined))
      return false;
    b.combined_attribute = combined != 0;
  }
  for (auto* list : {&out.inputs, &out.outputs}) {
    if (!r.u32(n) || !r.room_for(n, 44)) return false;
    list->resize(n);
    for (InterfaceVariable& v : *list) {
      uint32_t base = 0, flat = 0, patch = 0;
      if (!r.str(v.name) || !r.u32(v.variable) || !r.u32(base) || !r.u32(v.location) || !r.u32(v.component) ||
          !r.u32(v.bit_width) || !r.u32(v.vector_size) || !r.u32(v.columns) || !r.u32(v.array_size) ||
          !r.u32(flat) || !r.u32(patch) || base > uint32_t(InterfaceVariable::Base::other))
        return false;
      v.base = InterfaceVariable::Base(base), v.flat = flat != 0, v.patch = patch != 0;
    }
  }
  if (!r.u32(n) || !r.room_for(n, 16)) return false;
  out.constants.resize(n);
  for (ReflectedConstant& c : out.constants) {
    uint32_t kind = 0;
    if (!r.str(c.name) || !r.u32(kind) || !r.u32(c.constant_id) || !r.u32(c.size) ||
        kind > uint32_t(ReflectedConstant::Kind::other))
      return false;
    c.kind = ReflectedConstant::Kind(kind);
  }
  return r.u32(out.push_constant_size) && r.str(out.push_constant_name) && r.str(out.error) &&
         r.str(out.unsupported);
}

uint32_t get_u32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
}
uint64_t get_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= uint64_t(p[i]) << (8 * i);
  return v;
}
void put_u64(std::vector<uint8_t>& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(uint8_t(v >> (8 * i)));
}

bool is_entry_name(std::string_view name) {
  return name.size() == 64 && name.find_first_not_of("0123456789abcdef") == std::string_view::npos;
}

// The signature of an entry: HMAC-SHA-256 under the team's key of the entry's key and payload hash.
Digest signature(std::span<const uint8_t> secret, const CacheKey& key, const Digest& payload_hash) {
  uint8_t message[64];
  std::copy(key.begin(), key.end(), message);
  std::copy(payload_hash.begin(), payload_hash.end(), message + 32);
  return hmac_sha256(secret, message);
}

// Why `header` (kHeaderBytes) and `payload` are not a whole entry stored under `key` (magic, layout
// version, key, payload size and SHA-256, and with a team key its signature), or "".
std::string_view entry_problem(const uint8_t* header, std::span<const uint8_t> payload, const CacheKey& key,
                               std::span<const uint8_t> secret) {
  if (std::memcmp(header, kMagic, 4) != 0 || get_u32(header + 4) != kEntryVersion) return "not an entry";
  if (std::memcmp(header + 8, key.data(), key.size()) != 0) return "stored under another key";
  if (get_u64(header + 40) != payload.size()) return "truncated";
  Digest stored, hash = sha256(payload);
  std::copy_n(header + 48, stored.size(), stored.begin());
  if (stored != hash) return "damaged (its payload hash does not match)";
  if (secret.empty()) return "";
  std::copy_n(header + 80, stored.size(), stored.begin());
  return same_digest(stored, signature(secret, key, hash)) ? "" : "not signed with the team's key";
}

// An entry's header (bytes 0..111, signed when a team key is set) for `payload` (then `payload_tail`).
std::vector<uint8_t> entry_header(const CacheKey& key, std::span<const uint8_t> payload,
                                  std::span<const uint8_t> secret,
                                  std::span<const uint8_t> payload_tail = {}) {
  std::vector<uint8_t> bytes(kMagic, kMagic + 4);
  put_u32(bytes, kEntryVersion);
  bytes.insert(bytes.end(), key.begin(), key.end());
  put_u64(bytes, payload.size() + payload_tail.size());
  const Digest hash =
      payload_tail.empty() ? sha256(payload) : Sha256().update(payload).update(payload_tail).finish();
  bytes.insert(bytes.end(), hash.begin(), hash.end());
  const Digest signed_by = secret.empty() ? Digest{} : signature(secret, key, hash);
  bytes.insert(bytes.end(), signed_by.begin(), signed_by.end());
  return bytes;
}

// An entry's bytes: the header, then the payload.
std::vector<uint8_t> encode_entry(const CacheKey& key, std::span<const uint8_t> payload,
                                  std::span<const uint8_t> secret) {
  std::vector<uint8_t> bytes = entry_header(key, payload, secret);
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  return bytes;
}

// Every entry (and temporary) of one subdirectory, oldest use first.
struct FileOnDisk {
  int64_t mtime;
  uint64_t size;
  fs::path path;
  bool temporary;
};
std::vector<FileOnDisk> files_of(const fs::path& subdir) {
  std::vector<FileOnDisk> out;
  DIR* d = ::opendir(subdir.c_str());
  if (!d) return out;
  while (dirent* e = ::readdir(d)) {
    const std::string_view name = e->d_name;
    const bool temporary = name.starts_with(".tmp-");
    if (!temporary && !is_entry_name(name)) continue;
    struct stat st {};
    if (::fstatat(::dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
    out.push_back({int64_t(st.st_mtime), uint64_t(st.st_size), subdir / e->d_name, temporary});
  }
  ::closedir(d);
  std::sort(out.begin(), out.end(),
            [](const FileOnDisk& a, const FileOnDisk& b) { return a.mtime < b.mtime; });
  return out;
}

// Removes the oldest entries of `files` until the entries hold at most `target` bytes (temporaries do
// not count: another pack may be writing them), never one named in `keep` (written by this run), and
// temporaries of runs that died.
// The bytes of the entries among `files` (temporaries do not count).
uint64_t entry_bytes(const std::vector<FileOnDisk>& files) {
  uint64_t total = 0;
  for (const auto& f : files)
    if (!f.temporary) total += f.size;
  return total;
}

size_t trim(std::vector<FileOnDisk>& files, uint64_t target, const std::set<std::string>& keep = {}) {
  uint64_t total = entry_bytes(files);
  size_t removed = 0;
  const int64_t now = int64_t(::time(nullptr));
  std::vector<FileOnDisk> kept;
  for (auto& f : files) {
    const bool dead_temporary = f.temporary && now - f.mtime > kStaleTemporarySeconds;
    const bool evict = !f.temporary && total > target && !keep.count(f.path.filename().string());
    if ((dead_temporary || evict) && ::unlink(f.path.c_str()) == 0) {
      if (!f.temporary) total -= f.size;
      ++removed;
      continue;
    }
    kept.push_back(std::move(f));
  }
  files = std::move(kept);
  return removed;
}

// Every entry and temporary of the cache's subdirectories (real directories only), oldest use first.
std::vector<FileOnDisk> all_files(const fs::path& root) {
  std::vector<FileOnDisk> all;
  for (size_t i = 0; i < kSubdirectories; ++i) {
    static const char digits[] = "0123456789abcdef";
    const fs::path subdir = root / std::string{digits[i >> 4], digits[i & 15]};
    struct stat st {};
    if (::lstat(subdir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) continue;
    auto files = files_of(subdir);
    all.insert(all.end(), files.begin(), files.end());
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const FileOnDisk& a, const FileOnDisk& b) { return a.mtime < b.mtime; });
  return all;
}

// The entries' bytes as the last pack that wrote left them: DIR/v2/size, one decimal number. Packs sharing
// the cache may overwrite each other's count (each adds what it wrote to what it read), so it can lag
// behind; a count over the bound, a missing or unreadable one, lists the directories and is written
// again exact. `cache prune` writes it exact too.
constexpr const char* kSizeFile = "size";
// (Not detail::read_regular_file: that follows links, and nothing under the cache is read through one.)
std::optional<uint64_t> read_size(const fs::path& root) {
  const int fd = ::open((root / kSizeFile).c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  char text[32] = {};
  const ssize_t n = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  if (n <= 0) return std::nullopt;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text, &end, 10);
  if (end == text || (*end != '\n' && *end != 0)) return std::nullopt;
  return uint64_t(value);
}
void write_size(const fs::path& root, uint64_t bytes) {
  const std::string text = std::to_string(bytes) + "\n";
  (void)detail::write_file_atomically(root / kSizeFile,
                                      {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
}

// Whether `dir` is a cache directory (its layout directory is a real directory); else `error` says so.
bool is_cache_directory(const fs::path& dir, std::string& error) {
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(dir / kLayoutDirectory, ec))) return true;
  error = "'" + printable(dir.string()) + "' is not a statepack cache directory (no " +
          std::string(kLayoutDirectory) + "/ in it)";
  return false;
}

// A subdirectory that is a real directory (created if missing), never a link planted in its place.
bool usable_subdirectory(const fs::path& path) {
  if (::mkdir(path.c_str(), 0755) == 0) return true;
  struct stat st {};
  return errno == EEXIST && ::lstat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace

CompileCache::CompileCache(fs::path dir, uint64_t max_bytes) : dir_(std::move(dir)), max_bytes_(max_bytes) {}
CompileCache::CompileCache(CompileCache&& o) noexcept
    : dir_(std::move(o.dir_)),
      max_bytes_(o.max_bytes_),
      pending_(std::move(o.pending_)),
      used_(std::move(o.used_)),
      flushed_(std::move(o.flushed_)),
      hits_(o.hits_.load()),
      misses_(o.misses_.load()),
      damaged_(o.damaged_.load()),
      written_(o.written_),
      removed_(o.removed_),
      memory_(std::move(o.memory_)),
      memory_bytes_(o.memory_bytes_),
      use_clock_(o.use_clock_),
      bundle_key_(o.bundle_key_),
      bundle_map_(std::move(o.bundle_map_)),  // the mapping moves: bundle_'s views stay valid
      bundle_(std::move(o.bundle_)),
      read_from_files_(std::move(o.read_from_files_)),
      from_bundle_(o.from_bundle_.load()),
      growth_(o.growth_),
      checked_subdirectories_(std::move(o.checked_subdirectories_)),
      remote_(std::move(o.remote_)),
      secret_(std::move(o.secret_)),
      remote_hits_(o.remote_hits_),
      remote_refused_(o.remote_refused_),
      first_refusal_(std::move(o.first_refusal_)) {}
CompileCache::~CompileCache() = default;

std::optional<CompileCache> CompileCache::open(const fs::path& dir, uint64_t max_bytes, std::string& error) {
  std::error_code ec;
  fs::create_directories(dir / kLayoutDirectory, ec);
  // v2 itself must be a directory, not a link planted in its place (everything is written below it).
  if (ec || !fs::is_directory(fs::symlink_status(dir / kLayoutDirectory, ec))) {
    error = "cannot use '" + printable(dir.string()) +
            "' as a cache directory: " + (ec ? ec.message() : std::string("not a directory"));
    return std::nullopt;
  }
  // The standard mark of a cache directory: backup tools skip it.
  const fs::path tag = dir / "CACHEDIR.TAG";
  if (!fs::exists(fs::symlink_status(tag, ec))) {
    constexpr std::string_view text =
        "Signature: 8a477f597d28d172789f06886806bc55\n# statepack's compile cache\n";
    (void)detail::write_file_atomically(tag, {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
  }
  return CompileCache(dir / kLayoutDirectory, max_bytes);
}

CompileCache CompileCache::in_memory(uint64_t max_bytes) {
  return CompileCache(fs::path(), max_bytes);
}

std::optional<std::vector<uint8_t>> CompileCache::read_entry(const CacheKey& key, const PayloadCheck& check) {
  const std::string name = hex(key);
  if (auto local = read_local(key, name)) return local;
  if (!remote_) return std::nullopt;
  // From the remote: checked as a local entry is (a server is written by other machines), then kept
  // in the local cache so that the next pack does not ask again.
  auto bytes = remote_->get(name, kMaxEntryBytes);
  if (!bytes) return std::nullopt;
  std::string_view problem = bytes->size() < kHeaderBytes ? "truncated" : "";
  const std::span<const uint8_t> payload =
      problem.empty() ? std::span<const uint8_t>(*bytes).subspan(kHeaderBytes) : std::span<const uint8_t>();
  if (problem.empty()) problem = entry_problem(bytes->data(), payload, key, secret_);
  std::string why(problem);
  // Unsigned, anyone who can write to the server could have made it: its module is validated as a fresh
  // one is. Signed with the team's key, it was written by a statepack of the team after that validation.
  if (why.empty() && check && secret_.empty()) why = check(payload);
  std::lock_guard lock(mutex_);
  if (!why.empty()) {
    if (remote_refused_++ == 0) first_refusal_ = name + ": " + why;
    return std::nullopt;
  }
  ++remote_hits_;
  std::vector<uint8_t> out(payload.begin(), payload.end());
  pending_.push_back({key, out, false});
  used_.insert(name);
  if (bundle_key_ && out.size() <= kMaxBundledPayload) read_from_files_.try_emplace(name, out);
  return out;
}

std::optional<std::vector<uint8_t>> CompileCache::read_local(const CacheKey& key, const std::string& name) {
  if (dir_.empty()) {
    std::lock_guard lock(mutex_);
    auto found = memory_.find(name);
    if (found == memory_.end()) return std::nullopt;
    found->second.last_used = ++use_clock_;
    used_.insert(name);
    return found->second.payload;
  }
  if (auto in_bundle = bundle_.find(name); in_bundle != bundle_.end()) {
    ++from_bundle_;
    std::lock_guard lock(mutex_);
    used_.insert(name);
    return std::vector<uint8_t>(in_bundle->second.begin(), in_bundle->second.end());
  }
  const fs::path path = dir_ / name.substr(0, 2) / name;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (errno != ENOENT) ++damaged_;  // a link planted there (ELOOP), or what cannot be read: rewritten
    return std::nullopt;
  }
  uint8_t header[kHeaderBytes];
  std::vector<uint8_t> bytes;  // the payload
  struct stat st {};
  bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && uint64_t(st.st_size) >= kHeaderBytes &&
            uint64_t(st.st_size) <= kMaxEntryBytes;
  // Reads exactly `size` bytes (a file that shrank underneath is a short read: damaged).
  auto read_all = [fd](uint8_t* to, size_t size) {
    size_t done = 0;
    while (done < size) {
      const ssize_t n = ::read(fd, to + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += size_t(n);
    }
    return done == size;
  };
  if (ok) {
    bytes.resize(size_t(st.st_size) - kHeaderBytes);
    ok = read_all(header, kHeaderBytes) && read_all(bytes.data(), bytes.size()) &&
         entry_problem(header, bytes, key, secret_).empty();
  }
  if (ok) {
    ::futimens(fd, nullptr);  // recently used: pruned last
    std::lock_guard lock(mutex_);
    used_.insert(name);
  }
  ::close(fd);
  if (!ok) {
    ++damaged_;  // truncated, damaged, unsigned or not ours: a miss, and written again
    return std::nullopt;
  }
  if (bundle_key_ && key != *bundle_key_ && bytes.size() <= kMaxBundledPayload) {  // (the next bundle's)
    std::lock_guard lock(mutex_);
    read_from_files_.try_emplace(name, bytes);
  }
  return bytes;
}

void CompileCache::use_bundle(std::string_view project) {
  if (dir_.empty()) return;  // a cache in memory has no files to save opening
  KeyBuilder k;
  bundle_key_ = k.add("bundle").add(code_identity()).add(project).key();
  const std::string name = hex(*bundle_key_);  // (mapped: a bundle of real-sized shaders is large)
  const auto mapped = map_entry(dir_ / name.substr(0, 2) / name, damaged_);
  if (!mapped) return;
  const size_t size = mapped->size;
  bundle_map_ = mapped->map;
  const uint8_t* header = bundle_map_.get();
  const std::span<const uint8_t> all(header + kHeaderBytes, size - kHeaderBytes);
  bool ok = entry_problem(header, all, *bundle_key_, secret_).empty();
  // (32-byte key, u64 size, payload) until the end; anything out of place drops the whole bundle.
  for (size_t at = 0; ok && at < all.size();) {
    if (all.size() - at < 40 || get_u64(&all[at + 32]) > all.size() - at - 40) {
      ok = false;
      break;
    }
    CacheKey key;
    std::copy_n(&all[at], key.size(), key.begin());
    const size_t entry = size_t(get_u64(&all[at + 32]));
    bundle_.insert_or_assign(hex(key), all.subspan(at + 40, entry));
    at += 40 + entry;
  }
  if (!ok) {
    ++damaged_;
    bundle_.clear();
    bundle_map_.reset();
  }
}

std::optional<CompileCache::LocalEntry> CompileCache::find_local(const CacheKey& key) {
  const std::string name = hex(key);
  if (dir_.empty()) {
    auto payload = read_local(key, name);
    if (!payload) return std::nullopt;
    auto held = std::make_shared<const std::vector<uint8_t>>(std::move(*payload));
    return LocalEntry{std::shared_ptr<const void>(held, held->data()), *held};
  }
  const auto mapped = map_entry(dir_ / name.substr(0, 2) / name, damaged_);
  if (!mapped) return std::nullopt;
  const std::span<const uint8_t> payload(mapped->map.get() + kHeaderBytes, mapped->size - kHeaderBytes);
  if (!entry_problem(mapped->map.get(), payload, key, secret_).empty()) {
    ++damaged_;  // written again
    return std::nullopt;
  }
  std::lock_guard lock(mutex_);
  used_.insert(name);
  return LocalEntry{mapped->map, payload};
}

std::optional<fs::file_time_type> CompileCache::local_time(const CacheKey& key) const {
  if (dir_.empty()) return std::nullopt;
  const std::string name = hex(key);
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(dir_ / name.substr(0, 2) / name, ec);
  if (ec || !fs::is_regular_file(status)) return std::nullopt;
  const auto time = fs::last_write_time(dir_ / name.substr(0, 2) / name, ec);
  if (ec) return std::nullopt;
  return time;
}

void CompileCache::keep(const CacheKey& key, std::vector<uint8_t> payload) {
  std::lock_guard lock(mutex_);
  pending_.push_back({key, std::move(payload), true});
}

std::optional<CompileCache::Compile> CompileCache::find_compile(const ShaderDesc& shader,
                                                                const CompileOptions& options,
                                                                const KnownText* known) {
  Compile found;
  CompiledShader& out = found.compiled;
  if (known && !shader.file.empty()) {
    out.files_read.push_back(known->file);
    out.source_hash = known->hash;
  } else {
    const std::optional<InputText> source = shader_text(shader, options);
    if (!source) return std::nullopt;  // the compile reports why
    if (!shader.file.empty())
      out.files_read.push_back({(working_directory() / shader.file).lexically_normal(), source->identity});
    out.source_hash = text_hash(source->text);
  }
  auto payload = read_entry(compile_key(shader, options, out.source_hash));
  uint32_t flags = 0, count = 0;
  PayloadReader r(payload ? std::span<const uint8_t>(*payload) : std::span<const uint8_t>());
  // An #include record takes at least 45 bytes.
  if (!payload || !r.u32(flags) || !r.u32(count) || !r.room_for(count, 45)) {
    if (payload) ++damaged_;
    ++misses_;
    return std::nullopt;
  }
  // Every #include glslang asked for: found in the same place, with the same text.
  uint64_t included = 0;
  for (uint32_t i = 0; i < count; ++i) {
    IncludeRecord rec;
    if (!read_include_record(r, rec)) return ++damaged_, ++misses_, std::nullopt;
    auto file = include_still_holds(rec, options, included);
    if (!file) return ++misses_, std::nullopt;
    out.files_read.push_back(std::move(*file));
    out.includes.push_back(std::move(rec));
  }
  uint32_t names = 0;
  if (!r.u32(names) || !r.room_for(names, 4)) return ++damaged_, ++misses_, std::nullopt;
  out.combined_image_samplers.resize(names);
  for (auto& n : out.combined_image_samplers)
    if (!r.str(n)) return ++damaged_, ++misses_, std::nullopt;
  uint32_t semantics = 0;
  if (!r.u32(semantics) || !r.room_for(semantics, 8)) return ++damaged_, ++misses_, std::nullopt;
  out.vertex_semantics.resize(semantics);
  for (auto& v : out.vertex_semantics)
    if (!r.u32(v.variable) || !r.str(v.semantic)) return ++damaged_, ++misses_, std::nullopt;
  if (!r.str(out.entry_point)) return ++damaged_, ++misses_, std::nullopt;
  if (!r.words(out.spirv) || out.spirv.empty()) return ++damaged_, ++misses_, std::nullopt;
  if (flags & 2) {
    if (!read_reflection(r, found.reflection.emplace())) return ++damaged_, ++misses_, std::nullopt;
  }
  if (!r.done()) return ++damaged_, ++misses_, std::nullopt;
  out.backend_specific = flags & 1;
  out.ok = true;
  ++hits_;
  return found;
}

void CompileCache::keep_compile(const ShaderDesc& shader, const CompileOptions& options,
                                const CompiledShader& compiled, const Reflection* reflection) {
  if (!compiled.ok) return;
  PayloadWriter w;
  w.u32((compiled.backend_specific ? 1 : 0) | (reflection ? 2 : 0));
  w.u32(uint32_t(compiled.includes.size()));
  for (const IncludeRecord& rec : compiled.includes) write_include_record(w, rec);
  w.u32(uint32_t(compiled.combined_image_samplers.size()));
  for (const auto& n : compiled.combined_image_samplers) w.str(n);
  w.u32(uint32_t(compiled.vertex_semantics.size()));
  for (const auto& v : compiled.vertex_semantics) w.u32(v.variable), w.str(v.semantic);
  w.str(compiled.entry_point);
  w.words(compiled.spirv);
  if (reflection) write_reflection(w, *reflection);
  keep(compile_key(shader, options, compiled.source_hash), std::move(w.bytes));
}

std::optional<std::vector<uint32_t>> CompileCache::find_finalized(const std::vector<uint32_t>& input,
                                                                  const CompileOptions& options) {
  // A finalised module from a server passes the validation a fresh one ends with before it is used.
  auto validate = [&](std::span<const uint8_t> payload) -> std::string {
    std::vector<uint32_t> words;
    PayloadReader r(payload);
    if (!r.words(words) || !r.done() || words.empty()) return "not a module";
    const std::string error = validate_spirv(words, options);
    return error.empty() ? "" : "its module " + error.substr(error.find("fails"));
  };
  auto payload = read_entry(finalize_key(input, options), validate);
  std::vector<uint32_t> words;
  PayloadReader r(payload ? std::span<const uint8_t>(*payload) : std::span<const uint8_t>());
  if (!payload || !r.words(words) || !r.done() || words.empty()) {
    if (payload) ++damaged_;
    ++misses_;
    return std::nullopt;
  }
  ++hits_;
  return words;
}

void CompileCache::keep_finalized(const std::vector<uint32_t>& input, const CompileOptions& options,
                                  const std::vector<uint32_t>& output) {
  PayloadWriter w;
  w.words(output);
  keep(finalize_key(input, options), std::move(w.bytes));
}

// A cache in memory: what was kept goes into the map, then the least recently used entries leave it
// until it is within its bound, never one this run wrote or read.
std::string CompileCache::flush_to_memory() {
  std::lock_guard lock(mutex_);
  write_to_remote(pending_);
  std::set<std::string> keep = std::move(used_);
  used_.clear();
  // The last result kept under a name wins (a compile made again under its key, after its #includes
  // changed, replaces what was there and what a server returned for it).
  std::set<std::string> done;
  for (auto p = pending_.rbegin(); p != pending_.rend(); ++p) {
    std::string name = hex(p->key);
    keep.insert(name);
    if (!done.insert(name).second) continue;  // the same result twice in one run
    auto [it, inserted] = memory_.try_emplace(std::move(name));
    if (!inserted) memory_bytes_ -= it->second.payload.size();
    memory_bytes_ += p->payload.size();
    it->second = {std::move(p->payload), ++use_clock_};
    ++written_;
  }
  pending_.clear();
  if (memory_bytes_ <= max_bytes_) return "";
  std::vector<std::pair<uint64_t, std::string>> by_use;
  for (const auto& [name, entry] : memory_)
    if (!keep.count(name)) by_use.emplace_back(entry.last_used, name);
  std::sort(by_use.begin(), by_use.end());
  for (const auto& [last_used, name] : by_use) {
    if (memory_bytes_ <= max_bytes_) break;
    auto it = memory_.find(name);
    memory_bytes_ -= it->second.payload.size();
    memory_.erase(it);
    ++removed_;
  }
  return "";
}

bool CompileCache::write_entry(const CacheKey& key, std::span<const uint8_t> payload,
                               const std::set<FileIdentity>& inputs, std::string& warning,
                               std::span<const uint8_t> payload_tail) {
  const std::string name = hex(key);
  const fs::path subdir = dir_ / name.substr(0, 2), path = subdir / name;
  // Each subdirectory checked (and made) once per flush: a system call per entry was a tenth of a cold
  // pack of small shaders.
  if (!checked_subdirectories_.count(name.substr(0, 2))) {
    if (!usable_subdirectory(subdir)) {
      warning = "'" + printable(subdir.string()) + "' is not a directory";
      return false;
    }
    checked_subdirectories_.insert(name.substr(0, 2));
  }
  // The entry itself (not what a link planted there points to: rename() replaces the link).
  struct stat st {};
  const bool replaces = ::lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
  if (replaces && inputs.count(FileIdentity{uint64_t(st.st_dev), uint64_t(st.st_ino)})) {
    warning = "'" + printable(path.string()) + "' is one of this run's inputs; not replaced";
    return false;
  }
  const std::vector<uint8_t> header = entry_header(key, payload, secret_, payload_tail);
  if (!write_beside_and_rename(path, {header, payload, payload_tail}, warning)) return false;
  growth_ +=
      int64_t(header.size() + payload.size() + payload_tail.size()) - (replaces ? int64_t(st.st_size) : 0);
  return true;
}

std::string CompileCache::write_bundle(const std::vector<Pending>& written,
                                       const std::set<FileIdentity>& inputs, std::string& warning) {
  if (!bundle_key_) return "";
  // What this pack used: read (from the bundle or from files) or written; small entries only. Opening a
  // file costs about as much as reading a few tens of kilobytes, so a large entry (a real-sized shader's
  // module) gains nothing in a bundle, while a bundle of them would be rewritten whole, tens of megabytes,
  // whenever one shader changed.
  std::map<std::string, std::span<const uint8_t>> used;
  {
    std::lock_guard lock(mutex_);
    for (const std::string& name : used_) {
      if (auto b = bundle_.find(name); b != bundle_.end())
        used.emplace(name, b->second);
      else if (auto f = read_from_files_.find(name); f != read_from_files_.end())
        used.emplace(name, f->second);
    }
  }
  // A rewritten entry (a compile whose #includes changed keeps its key) replaces what was read.
  for (const Pending& p : written) used.insert_or_assign(hex(p.key), p.payload);
  std::erase_if(used, [](const auto& entry) { return entry.second.size() > kMaxBundledPayload; });
  // Rewriting the bundle costs every small entry of the project: after one shader of a thousand changed
  // that was a few megabytes hashed and written for two new entries, a repack's cache writes growing
  // with the project instead of with the change. So the few entries a pack used beside it are read from
  // their own files (about an open each) until they, plus those it holds that went unused (a changed
  // shader's old compile), pass 1/32 of what the pack used: a rewrite every dozen or so one-shader edits
  // of a large project, every time in a small one. A name it holds that was written again (a compile
  // whose #includes changed keeps its key) is rewritten at once: its bytes there are stale, and would be
  // served and missed by every later pack.
  size_t outside = 0;
  for (const auto& entry : used) outside += bundle_.contains(entry.first) ? 0 : 1;
  const size_t unused = bundle_.size() - (used.size() - outside);
  const bool rewritten =
      std::ranges::any_of(written, [&](const Pending& p) { return bundle_.contains(hex(p.key)); });
  if (used.empty() || (!rewritten && (outside + unused) * kBundleSlack <= used.size())) return "";
  std::vector<uint8_t> payload;
  for (const auto& [name, bytes] : used) {
    const CacheKey key = key_of(name);
    payload.insert(payload.end(), key.begin(), key.end());
    put_u64(payload, bytes.size());
    payload.insert(payload.end(), bytes.begin(), bytes.end());
    if (payload.size() > kMaxEntryBytes - kHeaderBytes) return "";  // too large to read back: none
  }
  return write_entry(*bundle_key_, payload, inputs, warning) ? hex(*bundle_key_) : "";
}

// Trims the cache to its bound, least recently used first; `keep`, what the last flush wrote, what this
// run used, and its bundle stay. The directories are listed (a stat per entry) only when the size the last
// pack left in kSizeFile, plus what this one added, passes the bound, or when no size was left.
void CompileCache::trim_to_bound(std::set<std::string> keep) {
  {
    std::lock_guard lock(mutex_);
    keep.insert(used_.begin(), used_.end());
  }
  keep.insert(flushed_.begin(), flushed_.end());
  if (bundle_key_) keep.insert(hex(*bundle_key_));
  const std::optional<uint64_t> known = read_size(dir_);
  const int64_t estimate = known ? std::max<int64_t>(0, int64_t(*known) + growth_) : 0;
  if (known && uint64_t(estimate) <= max_bytes_) {
    write_size(dir_, uint64_t(estimate));
  } else {
    auto files = all_files(dir_);
    removed_ += trim(files, max_bytes_, keep);
    write_size(dir_, entry_bytes(files));
  }
  growth_ = 0;
}

std::string CompileCache::store_local(const CacheKey& key, std::span<const uint8_t> payload,
                                      std::span<const uint8_t> payload_tail,
                                      const std::vector<InputFile>& inputs) {
  if (kHeaderBytes + payload.size() + payload_tail.size() > kMaxEntryBytes) return "";  // never read back
  if (dir_.empty()) {
    std::vector<uint8_t> bytes(payload.begin(), payload.end());
    bytes.insert(bytes.end(), payload_tail.begin(), payload_tail.end());
    {
      std::lock_guard lock(mutex_);
      pending_.push_back({key, std::move(bytes), false});
    }
    return flush_to_memory();
  }
  std::set<FileIdentity> identities;
  for (const auto& f : inputs) identities.insert(f.identity);
  std::string warning;
  if (write_entry(key, payload, identities, warning, payload_tail)) trim_to_bound({hex(key)});
  checked_subdirectories_.clear();
  return warning;
}

std::string CompileCache::flush(const std::vector<InputFile>& inputs) {
  if (dir_.empty()) return flush_to_memory();
  std::vector<Pending> pending;
  {
    std::lock_guard lock(mutex_);
    pending.swap(pending_);
  }
  write_to_remote(pending);
  flushed_.clear();
  std::set<FileIdentity> input_identities;
  for (const auto& f : inputs) input_identities.insert(f.identity);
  std::set<std::string> subdirectories, done;
  std::vector<Pending> written;
  std::string warning;
  // The last result kept under a name wins (a compile made again under its key, after its #includes
  // changed, over what a server returned for it).
  for (Pending& p : std::ranges::reverse_view(pending)) {
    const std::string name = hex(p.key);
    if (!done.insert(name).second) continue;  // the same result twice in one run
    if (!write_entry(p.key, p.payload, input_identities, warning)) continue;
    ++written_;
    subdirectories.insert(name.substr(0, 2));
    written.push_back(std::move(p));
  }
  if (const std::string bundle = write_bundle(written, input_identities, warning); !bundle.empty()) {
    done.insert(bundle);
    subdirectories.insert(bundle.substr(0, 2));
  }
  flushed_ = done;
  // A run that wrote entries trims the cache to its bound (a run that wrote nothing reads no listing).
  if (!subdirectories.empty()) trim_to_bound({});
  checked_subdirectories_.clear();  // (the next flush may find them replaced)
  return warning;
}

CompileCache::Stats CompileCache::stats() const {
  std::lock_guard lock(mutex_);
  return {hits_.load(), misses_.load(),      damaged_.load(), written_,
          removed_,     from_bundle_.load(), remote_hits_,    remote_refused_};
}

std::string CompileCache::first_refusal() const {
  std::lock_guard lock(mutex_);
  return first_refusal_;
}

void CompileCache::write_to_remote(const std::vector<Pending>& pending) {
  if (!remote_) return;
  std::vector<std::pair<std::string, std::vector<uint8_t>>> entries;
  for (const Pending& p : pending)
    if (p.to_remote) entries.emplace_back(hex(p.key), encode_entry(p.key, p.payload, secret_));
  remote_->put_all(entries);
}

void write_include_record(PayloadWriter& w, const IncludeRecord& rec) {
  w.str(rec.header);
  w.str(rec.includer);
  w.bytes.push_back(rec.local ? 1 : 0);
  w.str(display_path(rec.path));  // (as glslang names it: the same in every checkout)
  w.bytes.insert(w.bytes.end(), rec.text_hash.begin(), rec.text_hash.end());
}

bool read_include_record(PayloadReader& r, IncludeRecord& rec) {
  uint8_t local = 0;
  if (!r.str(rec.header) || !r.str(rec.includer) || !r.raw(&local, 1) || !r.str(rec.path) ||
      !r.raw(rec.text_hash.data(), rec.text_hash.size()))
    return false;
  rec.local = local != 0;
  return true;
}

std::optional<fs::path> include_found_again(const IncludeRecord& rec, const CompileOptions& options) {
  fs::path path = resolve_include(rec.header, rec.includer, rec.local, options.include_dirs);
  if (path.empty() || display_path(path) != rec.path) return std::nullopt;
  return path;
}

std::optional<InputFile> include_still_holds(const IncludeRecord& rec, const CompileOptions& options,
                                             uint64_t& included, IncludeTexts* texts) {
  const auto found = include_found_again(rec, options);
  if (!found) return std::nullopt;
  const fs::path& path = *found;
  const std::string& name = rec.path;
  if (texts)
    if (auto known = texts->find(name); known != texts->end()) {
      included += known->second.size;
      if (known->second.hash != rec.text_hash || included > options.max_input_bytes) return std::nullopt;
      return known->second.file;
    }
  InputText input = read_input_file(path, name, options.max_input_bytes);
  if (!input.error.empty()) return std::nullopt;
  IncludeText text{text_hash(input.text),
                   input.text.size(),
                   {(working_directory() / path).lexically_normal(), input.identity}};
  if (texts) texts->insert_or_assign(name, text);
  included += text.size;
  if (text.hash != rec.text_hash || included > options.max_input_bytes) return std::nullopt;
  return text.file;
}

CacheKey compile_cache_key(const ShaderDesc& shader, const CompileOptions& options,
                           const CompileCache::KnownText& known) {
  return compile_key(shader, options, known.hash);
}

CacheKey compile_entry_key(const ShaderDesc& shader, const CompileOptions& options,
                           const Digest& source_hash) {
  return compile_key(shader, options, source_hash);
}

CacheKey finalized_entry_key(const std::vector<uint32_t>& input, const CompileOptions& options) {
  return finalize_key(input, options);
}

void CompileCache::note_used(const CacheKey& key) {
  const std::string name = hex(key);
  std::lock_guard lock(mutex_);
  if (dir_.empty()) {
    auto found = memory_.find(name);
    if (found == memory_.end()) return;
    found->second.last_used = ++use_clock_;
  }
  used_.insert(name);
}

std::optional<CacheKey> compile_cache_key(const ShaderDesc& shader, const CompileOptions& options,
                                          InputFile* file, Digest* text) {
  const std::optional<InputText> source = shader_text(shader, options);
  if (!source) return std::nullopt;
  if (file && !shader.file.empty())
    *file = {(working_directory() / shader.file).lexically_normal(), source->identity};
  const Digest hash = text_hash(source->text);
  if (text) *text = hash;
  return compile_key(shader, options, hash);
}

CompileCache::PruneResult CompileCache::prune(const fs::path& dir, uint64_t max_bytes) {
  PruneResult result;
  const fs::path root = dir / kLayoutDirectory;
  if (!is_cache_directory(dir, result.error)) return result;
  std::vector<FileOnDisk> all = all_files(root);
  for (const auto& f : all)
    if (!f.temporary) result.bytes_before += f.size, ++result.entries_before;
  trim(all, max_bytes);
  for (const auto& f : all)
    if (!f.temporary) result.bytes_after += f.size, ++result.entries_after;
  write_size(root, result.bytes_after);
  return result;
}

namespace {
constexpr char kTransferMagic[4] = {'S', 'P', 'K', 'X'};
constexpr uint32_t kTransferVersion = 1;
}  // namespace

CompileCache::TransferResult CompileCache::export_entries(const fs::path& dir, const fs::path& file) {
  TransferResult result;
  const fs::path root = dir / kLayoutDirectory;
  if (!is_cache_directory(dir, result.error)) return result;
  std::vector<uint8_t> out(kTransferMagic, kTransferMagic + 4);
  put_u32(out, kTransferVersion);
  std::vector<fs::path> entries;  // (the export may not replace one of them)
  for (const FileOnDisk& f : all_files(root)) {
    if (f.temporary) continue;
    // Whole entries under their own names only, never through a link planted among them (it could
    // point at any file of the user who exports).
    std::vector<uint8_t> entry;
    if (read_entry_file(f.path, kMaxEntryBytes, entry) != EntryRead::ok || entry.size() < kHeaderBytes ||
        !entry_problem(entry.data(), std::span(entry).subspan(kHeaderBytes),
                       key_of(f.path.filename().string()), {})
             .empty())
      continue;
    entries.push_back(f.path);
    put_u64(out, entry.size());
    out.insert(out.end(), entry.begin(), entry.end());
    ++result.entries, result.bytes += entry.size();
  }
  if (file.string() == "-") {
    std::fwrite(out.data(), 1, out.size(), stdout);
  } else if (auto written = detail::write_file_atomically(file, out, entries); !written) {
    result.error = written.error().message;
    result.exit_code = written.error().code == ErrorCode::invalid_argument ? 2 : 3;
  }
  return result;
}

CompileCache::TransferResult CompileCache::import_entries(const fs::path& dir, const fs::path& file,
                                                          std::span<const uint8_t> secret) {
  TransferResult result;
  std::string error;
  auto cache = open(dir, kDefaultMaxBytes, error);
  if (!cache) return result.error = error, result.exit_code = 3, result;
  cache->secret_.assign(secret.begin(), secret.end());
  InputText input = read_input_file(file, file.string(), uint64_t(64) << 30);
  if (!input.error.empty()) return result.error = input.error, result.exit_code = 3, result;
  const auto* bytes = reinterpret_cast<const uint8_t*>(input.text.data());
  const size_t size = input.text.size();
  if (size < 8 || std::memcmp(bytes, kTransferMagic, 4) != 0 || get_u32(bytes + 4) != kTransferVersion) {
    result.error = "'" + printable(file.string()) + "' is not an export of a statepack cache";
    result.exit_code = 1;
    return result;
  }
  std::set<FileIdentity> inputs{input.identity};
  for (size_t at = 8; at < size;) {
    if (size - at < 8 || get_u64(bytes + at) > size - at - 8 || get_u64(bytes + at) < kHeaderBytes) {
      result.error = "'" + printable(file.string()) + "' is truncated or damaged after " +
                     std::to_string(result.entries + result.present + result.refused) + " entries";
      result.exit_code = 1;
      break;
    }
    const size_t length = size_t(get_u64(bytes + at));
    const uint8_t* entry = bytes + at + 8;
    at += 8 + length;
    CacheKey key;
    std::copy_n(entry + 8, key.size(), key.begin());
    const std::span<const uint8_t> payload(entry + kHeaderBytes, length - kHeaderBytes);
    // (Without a team key, the file's writer decides what is stored under which key: an unsigned
    // import trusts the file as a copy of a cache directory would. Entries no read would accept are not
    // written.)
    if (length > kMaxEntryBytes || !entry_problem(entry, payload, key, secret).empty()) {
      ++result.refused;
      continue;
    }
    const std::string name = hex(key);
    struct stat st {};
    if (::lstat((cache->dir_ / name.substr(0, 2) / name).c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
      ++result.present;
      continue;
    }
    std::string warning;
    if (!cache->write_entry(key, payload, inputs, warning))
      return result.error = warning, result.exit_code = 3, result;
    ++result.entries, result.bytes += length;
  }
  write_size(cache->dir_, entry_bytes(all_files(cache->dir_)));
  return result;
}

}  // namespace statepack::packager
