// The names of the error codes (result.hpp).
#include "statepack/result.hpp"

namespace statepack {

const char* to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::io_error:
      return "io_error";
    case ErrorCode::bad_magic:
      return "bad_magic";
    case ErrorCode::unsupported_version:
      return "unsupported_version";
    case ErrorCode::truncated:
      return "truncated";
    case ErrorCode::corrupt:
      return "corrupt";
    case ErrorCode::checksum_mismatch:
      return "checksum_mismatch";
    case ErrorCode::content_version_mismatch:
      return "content_version_mismatch";
    case ErrorCode::misaligned_memory:
      return "misaligned_memory";
    case ErrorCode::not_found:
      return "not_found";
    case ErrorCode::wrong_type:
      return "wrong_type";
    case ErrorCode::missing_backend:
      return "missing_backend";
    case ErrorCode::unsupported:
      return "unsupported";
    case ErrorCode::layout_changed:
      return "layout_changed";
    case ErrorCode::vulkan_error:
      return "vulkan_error";
    case ErrorCode::invalid_argument:
      return "invalid_argument";
    case ErrorCode::out_of_memory:
      return "out_of_memory";
    case ErrorCode::gl_error:
      return "gl_error";
    case ErrorCode::cancelled:
      return "cancelled";
  }
  return "unknown";
}

}  // namespace statepack
