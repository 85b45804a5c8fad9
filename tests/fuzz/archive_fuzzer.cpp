// libFuzzer target for the archive reader: any bytes must be rejected cleanly or decode into contents
// that encode and decode again. Built with clang (-fsanitize=fuzzer,address,undefined) by
// tests/CMakeLists.txt and run for a bounded time by the test `fuzz.archive_reader`. The build defines
// FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION, so the reader skips its checksums and mutations reach the
// structural checks (offsets, counts, indices, enums) instead of stopping at the hash. Whatever decodes
// then goes through the semantic checks (SPIR-V walk, shaders against stored layouts), as Archive
// loading does; and the input's words go to the SPIR-V walker directly, so it is fuzzed on its own too.
#include <cstring>
#include <vector>

#include "format/archive_format.hpp"
#include "format/semantic_check.hpp"
#include "format/spirv_walk.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint32_t> aligned((size + 3) / 4);  // the reader requires 4-byte alignment
  if (size > 0) std::memcpy(aligned.data(), data, size);
  (void)statepack::spirv::walk(std::span<const uint32_t>(aligned.data(), size / 4));
  auto decoded = statepack::format::decode({reinterpret_cast<const uint8_t*>(aligned.data()), size});
  if (!decoded) return 0;
  (void)statepack::format::check_shader_interfaces(*decoded);
  // The OpenGL block's checks, as statepack_gl runs them: the SPIR-V ones only on records that passed.
  if (statepack::format::validate_gl(*decoded)) (void)statepack::format::check_gl_shader_interfaces(*decoded);
  // Whatever the reader accepts must survive a round trip.
  std::vector<uint8_t> again = statepack::format::encode(*decoded);
  std::vector<uint32_t> again_aligned((again.size() + 3) / 4);
  std::memcpy(again_aligned.data(), again.data(), again.size());
  auto redecoded =
      statepack::format::decode({reinterpret_cast<const uint8_t*>(again_aligned.data()), again.size()});
  if (!redecoded || redecoded->pipelines.size() != decoded->pipelines.size()) __builtin_trap();
  return 0;
}
