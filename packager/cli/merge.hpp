// `statepack merge`: one archive from several. SPIR-V, shaders, samplers, set layouts and render passes
// that several inputs hold are stored once; an object name defined differently in two inputs is an
// error naming both files. The bytes depend only on the inputs and their order.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <vector>

namespace statepack::packager {

struct MergeOptions {
  std::vector<std::filesystem::path> inputs;
  std::filesystem::path output;
  std::optional<uint32_t> content_version;  // default: the inputs' when they agree, else an error
};

int run_merge(const MergeOptions& options, std::ostream& out, std::ostream& err);

}  // namespace statepack::packager
