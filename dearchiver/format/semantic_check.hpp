// Checks that an archive's records agree with its SPIR-V: what a checksum cannot promise once someone
// edits an archive and re-seals it. No Vulkan here (the fuzzer runs it); the device's limits are
// checked at unpack time by device_limits.hpp.
#pragma once

#include <vector>

#include "archive_format.hpp"
#include "spirv_walk.hpp"

namespace statepack::format {

// Every shader's entry point exists in its module with the stored stage's execution model; every
// descriptor a pipeline's shader uses is in the pipeline's stored layout, of a compatible type, with
// enough descriptors and visible to that stage; push constant blocks fit the stored push constant
// range; every vertex input location a vertex shader reads has an attribute. The error names the
// pipeline or shader, the binding and the reason.
// `walked`, when given, receives each blob's walk (by blob index; default-constructed for a blob no
// shader uses), so that the runtime does not walk them again.
Result<void> check_shader_interfaces(const Contents& contents, uint32_t threads = 1,
                                     std::vector<spirv::Module>* walked = nullptr);

// The same for the OpenGL block, whose records validate_gl has checked: each stage's entry point, no
// push constants, only capabilities OpenGL 4.5 with GL_ARB_gl_spirv has, every resource bound in its
// namespace.
Result<void> check_gl_shader_interfaces(const Contents& contents);

}  // namespace statepack::format
