// Archive: loads bytes (owned or borrowed) and keeps their validated, decoded contents.
#include "api_guard.hpp"
#include "archive_format.hpp"
#include "file_io.hpp"
#include "semantic_check.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack {

struct Archive::State {
  std::vector<uint32_t> owned;  // uint32_t storage keeps file bytes 4-byte aligned for SPIR-V
  format::Contents contents;
};

Archive::Archive(std::unique_ptr<State> state) : state_(std::move(state)) {}
Archive::Archive(Archive&&) noexcept = default;
Archive& Archive::operator=(Archive&&) noexcept = default;
Archive::~Archive() = default;

namespace {
Result<format::Contents> decode_checked(std::span<const uint8_t> bytes, std::optional<uint32_t> required,
                                        const std::string& origin) {
  auto decoded = format::decode(bytes);
  if (!decoded) return Error{decoded.error().code, origin + ": " + decoded.error().message};
  // What the SPIR-V declares must agree with the stored layouts before anything reaches Vulkan.
  if (auto consistent = format::check_shader_interfaces(*decoded); !consistent)
    return Error{consistent.error().code, origin + ": " + consistent.error().message};
  if (required && decoded->content_version != *required)
    return Error{ErrorCode::content_version_mismatch, origin + ": content version " +
                                                          std::to_string(decoded->content_version) +
                                                          ", required " + std::to_string(*required)};
  return decoded;
}
}  // namespace

Result<Archive> Archive::from_file(const std::filesystem::path& path, std::optional<uint32_t> required) {
  return api_guard("Archive::from_file", [&]() -> Result<Archive> {
    // Record offsets are 32-bit, so no valid archive is larger than 4 GiB.
    auto file = read_regular_file(path, uint64_t{0xFFFFFFFFu});
    if (!file) return file.error();
    auto state = std::make_unique<State>();
    state->owned = std::move(file->words);
    std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(state->owned.data()), file->size);
    auto decoded = decode_checked(bytes, required, path.string());
    if (!decoded) return decoded.error();
    state->contents = std::move(decoded.value());
    return Archive(std::move(state));
  });
}

Result<Archive> Archive::from_memory(std::span<const uint8_t> bytes, std::optional<uint32_t> required) {
  return api_guard("Archive::from_memory", [&]() -> Result<Archive> {
    auto decoded = decode_checked(bytes, required, "archive in memory");
    if (!decoded) return decoded.error();
    auto state = std::make_unique<State>();
    state->contents = std::move(decoded.value());
    return Archive(std::move(state));
  });
}

uint32_t Archive::content_version() const {
  return state_->contents.content_version;
}
uint32_t Archive::format_version() const {
  return state_->contents.format_version;
}
const format::Contents& Archive::contents() const {
  return state_->contents;
}

std::vector<ObjectInfo> Archive::objects() const {
  const format::Contents& c = state_->contents;
  std::vector<ObjectInfo> out;
  for (const auto& p : c.pipelines)
    out.push_back({p.name, p.kind == format::PipelineKind::compute ? ObjectKind::compute_pipeline
                                                                   : ObjectKind::graphics_pipeline});
  for (const auto& l : c.set_layouts)
    if (!l.name.empty()) out.push_back({l.name, ObjectKind::resource_signature});
  for (const auto& r : c.render_passes) out.push_back({r.name, ObjectKind::render_pass});
  for (uint32_t s : c.standalone_shaders) out.push_back({c.shaders[s].name, ObjectKind::shader});
  return out;
}

}  // namespace statepack
