#include "archive_file.hpp"

#include "support/failure.hpp"

#include "semantic_check.hpp"
#include "support/file_io.hpp"

namespace statepack::format {

Result<Contents> load_archive(std::span<const uint8_t> bytes, std::optional<uint32_t> required,
                              const std::string& origin, uint32_t threads,
                              std::vector<spirv::Module>* walked) {
  auto decoded = decode(bytes);
  if (!decoded) return detail::failure(decoded.error().code, origin + ": " + decoded.error().message);
  // What the SPIR-V declares must agree with the stored layouts before anything reaches Vulkan.
  if (auto consistent = check_shader_interfaces(*decoded, threads, walked); !consistent)
    return detail::failure(consistent.error().code, origin + ": " + consistent.error().message);
  if (required && decoded->content_version != *required)
    return detail::failure(ErrorCode::content_version_mismatch,
                           origin + ": content version " + std::to_string(decoded->content_version) +
                               ", required " + std::to_string(*required));
  return decoded;
}

Result<void> check_opengl(const Contents& contents, const std::string& origin) {
  if (auto valid = validate_gl(contents); !valid)
    return detail::failure(valid.error().code, origin + ": " + valid.error().message);
  if (auto consistent = check_gl_shader_interfaces(contents); !consistent)
    return detail::failure(consistent.error().code, origin + ": " + consistent.error().message);
  return {};
}

Result<LoadedArchive> load_archive_file(const std::filesystem::path& path, std::optional<uint32_t> required) {
  auto file = detail::read_regular_file(path, uint64_t{0xFFFFFFFFu});
  if (!file) return file.error();
  LoadedArchive loaded;
  loaded.owned = std::move(file->words);
  std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(loaded.owned.data()), file->size);
  auto contents = load_archive(bytes, required, path.string(), 1, &loaded.modules);
  if (!contents) return contents.error();
  loaded.contents = std::move(contents.value());
  return loaded;
}

Result<Contents> load_archive_with_opengl(std::span<const uint8_t> bytes, std::optional<uint32_t> required,
                                          const std::string& origin, uint32_t threads) {
  auto contents = load_archive(bytes, required, origin, threads);
  if (!contents) return contents.error();
  if (auto checked = check_opengl(*contents, origin); !checked) return checked.error();
  return contents;
}

Result<LoadedArchive> load_archive_file_with_opengl(const std::filesystem::path& path) {
  auto loaded = load_archive_file(path);
  if (!loaded) return loaded.error();
  if (auto checked = check_opengl(loaded->contents, path.string()); !checked) return checked.error();
  return loaded;
}

}  // namespace statepack::format
