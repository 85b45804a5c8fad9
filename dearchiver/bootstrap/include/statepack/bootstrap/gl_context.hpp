// A headless OpenGL 4.5 core context for the samples and tests: EGL's surfaceless platform (Mesa's
// llvmpipe on a machine without a GPU, no X server), made current on the creating thread, with a
// GL_KHR_debug callback that records every error message (and every high-severity one) so that a test
// can fail on any.
#pragma once

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "statepack/result.hpp"

namespace statepack::bootstrap {

struct GlContextOptions {
  bool debug = true;              // a debug context with the message callback (synchronous output)
  bool require_llvmpipe = false;  // only accept Mesa's CPU renderer (tests: same results everywhere)
};

class GlContext {
 public:
  static Result<std::unique_ptr<GlContext>> create(const GlContextOptions& options = {});
  ~GlContext();  // releases and destroys the context
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes the context current on the calling thread (create() already did, for the creating thread).
  bool make_current() const;
  // Leaves the calling thread without a current context.
  bool release_current() const;

  std::string renderer;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version;   // GL_VERSION

  // Every recorded debug message so far: type GL_DEBUG_TYPE_ERROR or severity high, formatted with
  // the renderer's name.
  std::vector<std::string> error_messages() const;
  void clear_messages();

 private:
  GlContext() = default;
  static void GLAPIENTRY on_message(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                    const GLchar* message, const void* user);
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  mutable std::mutex mutex_;
  std::vector<std::string> messages_;
};

}  // namespace statepack::bootstrap
