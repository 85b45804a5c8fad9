// The public doors to statepack's own file, terminal and thread rules (support/): forwarding only, so
// the rules live in one place.
#include "statepack/bootstrap/host_tools.hpp"

#include "support/file_io.hpp"
#include "support/output_files.hpp"
#include "support/parallel_for.hpp"
#include "support/printable.hpp"

namespace statepack::bootstrap {

std::string printable(std::string_view text) {
  return detail::printable(text);
}

Result<std::vector<uint8_t>> read_file(const std::filesystem::path& path, uint64_t max_size) {
  auto file = detail::read_regular_file(path, max_size);
  if (!file) return file.error();
  auto bytes = file->bytes();
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
}

Result<void> write_file_atomically(const std::filesystem::path& path, std::span<const uint8_t> bytes,
                                   const std::vector<std::filesystem::path>& inputs) {
  return detail::write_file_atomically(path, bytes, inputs);
}

std::string output_refusal(const std::filesystem::path& path,
                           const std::vector<std::filesystem::path>& inputs) {
  std::vector<detail::InputFile> protected_inputs;
  for (const auto& input : inputs)
    if (auto id = detail::file_identity(input)) protected_inputs.push_back({input, *id});
  return detail::OutputSet(std::move(protected_inputs)).refuse_reason(path);
}

void parallel_for(size_t count, uint32_t threads, const std::function<void(size_t)>& work) {
  detail::parallel_for(count, threads, work);
}

}  // namespace statepack::bootstrap
