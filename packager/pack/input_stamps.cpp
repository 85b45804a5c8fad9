#include "input_stamps.hpp"

#include <sys/stat.h>

#include <map>
#include <set>
#include <utility>

#include "shaders/cache_payload.hpp"

namespace statepack::packager {
namespace {

namespace fs = std::filesystem;
constexpr uint32_t kStampsVersion = 4;

// A time as (seconds, nanoseconds) since the epoch: compared as a pair (nanoseconds alone overflow 64 bits
// in 2262, and a file's time may be set anywhere).
std::pair<int64_t, int64_t> pair_of(const timespec& t) {
  return {int64_t(t.tv_sec), int64_t(t.tv_nsec)};
}

void write_stamp(PayloadWriter& w, const FileStamp& s) {
  for (uint64_t v : {s.device, s.inode, s.size, uint64_t(s.modified.first), uint64_t(s.modified.second),
                     uint64_t(s.changed.first), uint64_t(s.changed.second)})
    w.u64(v);
}

bool read_stamp(PayloadReader& r, FileStamp& s) {
  uint64_t t[4] = {};
  if (!r.u64(s.device) || !r.u64(s.inode) || !r.u64(s.size) || !r.u64(t[0]) || !r.u64(t[1]) || !r.u64(t[2]) ||
      !r.u64(t[3]))
    return false;
  s.modified = {int64_t(t[0]), int64_t(t[1])}, s.changed = {int64_t(t[2]), int64_t(t[3])};
  return true;
}

void write_hint(PayloadWriter& w, const std::optional<TablesHint>& hint) {
  w.u32(hint ? 1 : 0);
  if (!hint) return;
  w.u32(uint32_t(hint->language));
  w.u32(hint->stage);
  w.u32(hint->glsl_version);
  w.str(hint->version_line);
}

// A hint as a notation could have made it: a known language, one of its stages, a GLSLVersion in the
// range the notation takes, and a #version line as version_line keeps it (200 characters and '\n').
bool read_hint(PayloadReader& r, std::optional<TablesHint>& hint) {
  uint32_t present = 0, language = 0;
  if (!r.u32(present) || present > 1) return false;
  if (!present) return true;
  hint.emplace();
  if (!r.u32(language) || language > uint32_t(SourceLanguage::spirv) || !r.u32(hint->stage) ||
      !r.u32(hint->glsl_version) || !r.str(hint->version_line))
    return false;
  hint->language = SourceLanguage(language);
  const bool one_stage = hint->stage != 0 && (hint->stage & (hint->stage - 1)) == 0 &&
                         hint->stage <= VK_SHADER_STAGE_COMPUTE_BIT;  // (the notation's six stages)
  return one_stage && hint->glsl_version <= 460 && hint->version_line.size() <= 201;
}

// The head of a stamps entry: enough to tell that it vouches for nothing, and to start glslang's tables.
struct StampsHead {
  CacheKey record{}, setup{};
  uint32_t unsettled = 0;  // files stat'ed within the racy window
  std::optional<TablesHint> tables;
};

bool read_head(PayloadReader& r, StampsHead& head) {
  uint32_t version = 0;
  return r.u32(version) && version == kStampsVersion && r.raw(head.record.data(), head.record.size()) &&
         r.raw(head.setup.data(), head.setup.size()) && r.u32(head.unsettled) && read_hint(r, head.tables);
}

// A stamps entry as written: what it vouches for, and each file with its stamp and whether the pack read
// it. Nothing is checked against the file system here.
struct ParsedStamps {
  StampedInputs inputs;
  struct File {
    std::string path;
    bool listed = false;
    FileStamp stamp;
  };
  std::vector<File> files;
};

std::optional<ParsedStamps> parse_stamps(std::span<const uint8_t> payload) {
  PayloadReader r(payload);
  ParsedStamps out;
  StampedInputs& in = out.inputs;
  StampsHead head;
  uint32_t lookups = 0, files = 0;
  if (!read_head(r, head) || !r.u32(lookups) || !r.room_for(lookups, 16)) return std::nullopt;
  in.record = head.record, in.setup = head.setup, in.tables = std::move(head.tables);
  in.lookups.resize(lookups);
  for (FileLookup& l : in.lookups) {
    uint32_t kind = 0;
    std::string base, found;
    if (!r.u32(kind) || kind > 1 || !r.str(l.name) || !r.str(base) || !r.str(found)) return std::nullopt;
    l.shader = kind == 1, l.base_dir = base, l.found = found;
  }
  if (!r.u32(files) || !r.room_for(files, 64)) return std::nullopt;
  out.files.resize(files);
  for (ParsedStamps::File& f : out.files) {
    uint32_t listed = 0;
    if (!r.str(f.path) || !r.u32(listed) || !read_stamp(r, f.stamp)) return std::nullopt;
    f.listed = listed != 0;
  }
  if (!r.done()) return std::nullopt;
  return out;
}

// Whether `lookup` found its name at the first place resolve_file looks (next to the notation, or the
// name itself when absolute): nothing can come before it, and the stamp of what it found (checked before
// the lookups) says it is still that regular file, so the search would find it again without a stat.
// Compared as text (found is normal, so equal text means the same place); any other spelling is
// searched again, which is only slower.
bool found_where_the_search_starts(const FileLookup& lookup) {
  const std::string &found = lookup.found.native(), &name = lookup.name, &base = lookup.base_dir.native();
  if (name.empty()) return false;
  if (name.front() == '/') return found == name;
  return found.size() == base.size() + 1 + name.size() && found.starts_with(base) &&
         found[base.size()] == '/' && found.ends_with(name);
}

}  // namespace

std::optional<FileStamp> stamp_of(const fs::path& path) {
  return stamp_of(path.native());
}

std::optional<FileStamp> stamp_of(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileStamp{uint64_t(st.st_dev), uint64_t(st.st_ino), uint64_t(st.st_size), pair_of(st.st_mtim),
                   pair_of(st.st_ctim)};
}

CacheKey stamps_slot(const CacheKey& record_slot) {
  return KeyBuilder().add("input stamps").add(record_slot).key();
}

RacyWindow::RacyWindow(std::chrono::system_clock::time_point started) {
  const auto since_epoch = (started - kRacyWindow).time_since_epoch();
  const auto seconds = std::chrono::floor<std::chrono::seconds>(since_epoch);
  before_ = {int64_t(seconds.count()), int64_t(std::chrono::nanoseconds(since_epoch - seconds).count())};
}

bool lookup_finds_the_same(const FileLookup& lookup, const NotationOptions& options) {
  return resolve_file(lookup.name, lookup.base_dir,
                      lookup.shader ? options.shader_dirs : options.render_state_dirs,
                      nullptr) == lookup.found;
}

std::optional<TakenStamps> take_input_stamps(const std::vector<FileLookup>& lookups,
                                             const std::vector<InputFile>& files,
                                             std::chrono::system_clock::time_point started) {
  const RacyWindow window(started);
  TakenStamps taken;
  PayloadWriter w;
  w.u32(uint32_t(lookups.size()));
  for (const FileLookup& l : lookups) {
    w.u32(l.shader ? 1 : 0);
    w.str(l.name);
    w.str(l.base_dir.string());
    w.str(l.found.string());
  }
  // Each file once (a pack lists an #include once per shader that includes it), and each name a lookup
  // found, stat'ed through any link: a notation file is listed by its canonical path, so a link given
  // as the input and pointed elsewhere changes only the stat of the name found. Those are stamped but
  // are not inputs of their own (the depfile and the output checks list the files read). Every stat must
  // find a file the pack read (its device and inode when read): one replaced or a link pointed elsewhere
  // while the pack ran, even at an older file, is not stamped.
  // (Keyed by the path's text: comparing std::filesystem::path objects walks their components.)
  std::map<std::string_view, std::optional<FileIdentity>> distinct;  // path -> as read, when it was read
  std::set<FileIdentity> read;
  for (const InputFile& f : files) distinct[f.path.native()] = f.identity, read.insert(f.identity);
  for (const FileLookup& l : lookups) distinct.try_emplace(l.found.native());
  w.u32(uint32_t(distinct.size()));
  for (const auto& [path, as_read] : distinct) {
    const auto stamp = stamp_of(std::string(path));
    if (!stamp) return std::nullopt;
    const FileIdentity now{stamp->device, stamp->inode};
    if (as_read ? now != *as_read : !read.count(now)) return std::nullopt;
    taken.unsettled += window.trusts(*stamp) ? 0 : 1;
    w.str(path);
    w.u32(as_read ? 1 : 0);
    write_stamp(w, *stamp);
  }
  taken.body = std::move(w.bytes);
  return taken;
}

std::string store_input_stamps(CompileCache& cache, const CacheKey& record_slot, const StampedInputs& stamped,
                               const TakenStamps& taken) {
  PayloadWriter head;
  head.u32(kStampsVersion);
  head.bytes.insert(head.bytes.end(), stamped.record.begin(), stamped.record.end());
  head.bytes.insert(head.bytes.end(), stamped.setup.begin(), stamped.setup.end());
  head.u32(taken.unsettled);
  write_hint(head, stamped.tables);
  return cache.store_local(stamps_slot(record_slot), head.bytes, taken.body, stamped.files);
}

std::string write_input_stamps(CompileCache& cache, const CacheKey& record_slot, const StampedInputs& stamped,
                               std::chrono::system_clock::time_point started) {
  const auto taken = take_input_stamps(stamped.lookups, stamped.files, started);
  return taken ? store_input_stamps(cache, record_slot, stamped, *taken) : "";
}

std::optional<StampedInputs> unchanged_inputs(CompileCache& cache, const CacheKey& record_slot,
                                              const CacheKey& setup, const NotationOptions& options) {
  const auto entry = cache.find_local(stamps_slot(record_slot));
  if (!entry) return std::nullopt;
  // Cheapest first, as a repack after an edit fails here: the head (a file stamped unsettled, the
  // options), each file's stat, then the lookups (a stat per directory searched).
  StampsHead head;
  PayloadReader r(entry->payload);
  if (!read_head(r, head) || head.unsettled || head.setup != setup) return std::nullopt;
  auto parsed = parse_stamps(entry->payload);
  if (!parsed) return std::nullopt;
  for (const ParsedStamps::File& f : parsed->files) {
    const auto now = stamp_of(f.path);
    if (!now || *now != f.stamp) return std::nullopt;
    if (f.listed) parsed->inputs.files.push_back({f.path, {f.stamp.device, f.stamp.inode}});
  }
  for (const FileLookup& l : parsed->inputs.lookups)
    if (!found_where_the_search_starts(l) && !lookup_finds_the_same(l, options)) return std::nullopt;
  return std::move(parsed->inputs);
}

std::optional<TablesHint> stamped_hint(std::span<const uint8_t> stamps) {
  PayloadReader r(stamps);
  StampsHead head;
  return read_head(r, head) ? head.tables : std::nullopt;
}

std::optional<TablesHint> hint_if_changed(std::span<const uint8_t> stamps) {
  PayloadReader r(stamps);
  StampsHead head;
  if (!read_head(r, head) || !head.tables) return std::nullopt;
  if (head.unsettled) return head.tables;  // (without reading on: a compile is as likely as after an edit)
  auto parsed = parse_stamps(stamps);      // (all of it: a damaged entry gives nothing)
  if (!parsed) return std::nullopt;
  for (const ParsedStamps::File& f : parsed->files)
    if (f.listed && stamp_of(f.path) != f.stamp) return parsed->inputs.tables;
  return std::nullopt;
}

}  // namespace statepack::packager
