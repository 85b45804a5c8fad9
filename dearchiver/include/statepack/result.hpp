// statepack — error values shared by the dearchiver API and the packager.
// No exceptions cross the library boundary: every fallible call returns Result<T>, whose error names
// the object involved and the reason.
#pragma once

#include <vulkan/vulkan_core.h>

#include <string>
#include <utility>
#include <variant>

#include "statepack/export.hpp"

namespace statepack {

enum class ErrorCode {
  io_error = 1,              // a file could not be read or written
  bad_magic,                 // the bytes are not a statepack archive
  unsupported_version,       // the archive needs a newer reader
  truncated,                 // the archive ends before a structure it declares
  corrupt,                   // an offset, size, count or enum in the archive is invalid
  checksum_mismatch,         // the whole-archive checksum or a blob's content hash does not match
  content_version_mismatch,  // the caller required another user content version
  misaligned_memory,         // caller-owned archive memory is not 4-byte aligned
  not_found,                 // no object of that name (the message suggests close names)
  wrong_type,                // the object exists but is another kind (e.g. compute vs graphics)
  missing_backend,           // the archive holds no data for the requested backend
  unsupported,               // the device lacks a feature the object needs
  vulkan_error,              // a Vulkan call failed; the message names the call and VkResult
  invalid_argument,          // the caller passed something unusable
  out_of_memory,             // an allocation failed
  gl_error,                  // an OpenGL shader did not specialize or a program did not link (driver's log)
  cancelled,                 // an unpack job ended (UnpackJob or Dearchiver destroyed) before creating it
  layout_changed,            // a reload would change a pipeline's layout or render targets: the old one stays
};

STATEPACK_API const char* to_string(ErrorCode code);

struct Error {
  ErrorCode code;
  std::string message;
  // For vulkan_error, what the failing call returned (VK_ERROR_OUT_OF_DEVICE_MEMORY, ...), so a caller can
  // react to it without parsing the message; VK_SUCCESS for every other code.
  VkResult vk_result = VK_SUCCESS;
};

// A value or an Error. Check with `if (result)` before `value()`.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::in_place_index<0>, std::move(value)) {}
  Result(Error error) : state_(std::in_place_index<1>, std::move(error)) {}

  bool has_value() const { return state_.index() == 0; }
  explicit operator bool() const { return has_value(); }

  T& value() & { return std::get<0>(state_); }
  const T& value() const& { return std::get<0>(state_); }
  T&& value() && { return std::get<0>(std::move(state_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }

  const Error& error() const { return std::get<1>(state_); }

 private:
  std::variant<T, Error> state_;
};

template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error error) : error_(std::move(error)), failed_(true) {}

  bool has_value() const { return !failed_; }
  explicit operator bool() const { return has_value(); }
  const Error& error() const { return error_; }

 private:
  Error error_{};
  bool failed_ = false;
};

}  // namespace statepack
