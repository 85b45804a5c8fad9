// Archive: owns (from_file) or borrows (from_memory) an archive's bytes and keeps their validated,
// decoded contents; the loading itself is the format library's.
#include "api_guard.hpp"
#include "archive_access.hpp"
#include "format/archive_file.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack {
using detail::api_guard;

struct Archive::State {
  format::LoadedArchive loaded;  // `owned` stays empty for borrowed bytes
};

Archive::Archive(std::unique_ptr<State> state) : state_(std::move(state)) {}
Archive::Archive(Archive&&) noexcept = default;
Archive& Archive::operator=(Archive&&) noexcept = default;
Archive::~Archive() = default;

Result<Archive> Archive::from_file(const std::filesystem::path& path, std::optional<uint32_t> required) {
  return api_guard("Archive::from_file", [&]() -> Result<Archive> {
    auto loaded = format::load_archive_file(path, required);
    if (!loaded) return loaded.error();
    return Archive(std::make_unique<State>(State{std::move(loaded.value())}));
  });
}

Result<Archive> Archive::from_memory(std::span<const uint8_t> bytes, std::optional<uint32_t> required) {
  return api_guard("Archive::from_memory", [&]() -> Result<Archive> {
    auto state = std::make_unique<State>();
    auto contents = format::load_archive(bytes, required, "archive in memory", 1, &state->loaded.modules);
    if (!contents) return contents.error();
    state->loaded.contents = std::move(contents.value());
    return Archive(std::move(state));
  });
}

uint32_t Archive::content_version() const {
  return state_->loaded.contents.content_version;
}
uint32_t Archive::format_version() const {
  return state_->loaded.contents.format_version;
}

std::vector<ObjectInfo> Archive::objects() const {
  const format::Contents& c = state_->loaded.contents;
  std::vector<ObjectInfo> out;
  for (const auto& p : c.pipelines)
    out.push_back({p.name, p.kind == format::PipelineKind::compute ? ObjectKind::compute_pipeline
                                                                   : ObjectKind::graphics_pipeline});
  detail::append_other_objects(c, out);
  return out;
}

namespace detail {
void append_other_objects(const format::Contents& c, std::vector<ObjectInfo>& out) {
  for (const auto& l : c.set_layouts)
    if (!l.name.empty()) out.push_back({l.name, ObjectKind::resource_signature});
  for (const auto& r : c.render_passes) out.push_back({r.name, ObjectKind::render_pass});
  for (uint32_t s : c.standalone_shaders) out.push_back({c.shaders[s].name, ObjectKind::shader});
}

const spirv::Module* ArchiveAccess::walked(const Archive& archive, uint32_t blob) {
  const auto& modules = archive.state_->loaded.modules;
  return blob < modules.size() ? &modules[blob] : nullptr;
}
void ArchiveAccess::discard(Archive& archive) {
  archive.state_.reset();
}
bool ArchiveAccess::discarded(const Archive& archive) {
  return !archive.state_;
}
uint64_t ArchiveAccess::file_hash(const Archive& archive) {
  const auto& owned = archive.state_->loaded.owned;
  return owned.empty() ? 0
                       : format::hash_bytes({reinterpret_cast<const uint8_t*>(owned.data()),
                                             owned.size() * sizeof(uint32_t)});
}
const format::Contents& ArchiveAccess::contents(const Archive& archive) {
  return archive.state_->loaded.contents;
}
}  // namespace detail

}  // namespace statepack
