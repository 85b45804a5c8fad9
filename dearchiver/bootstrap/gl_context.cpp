// Headless EGL (surfaceless platform) OpenGL 4.5 core context with a recording debug callback.
#include "statepack/bootstrap/gl_context.hpp"

#include <cstdio>

namespace statepack::bootstrap {

namespace {

Error fail(const std::string& what) {
  return Error{ErrorCode::unsupported, "OpenGL context: " + what};
}

const char* type_name(GLenum type) {
  switch (type) {
    case GL_DEBUG_TYPE_ERROR:
      return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
      return "deprecated behavior";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
      return "undefined behavior";
    case GL_DEBUG_TYPE_PORTABILITY:
      return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE:
      return "performance";
    default:
      return "other";
  }
}

}  // namespace

Result<std::unique_ptr<GlContext>> GlContext::create(const GlContextOptions& options) {
  if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
    return fail("EGL lacks EGL_MESA_platform_surfaceless (headless rendering)");
  std::unique_ptr<GlContext> gl(new GlContext());
  gl->display_ = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (gl->display_ == EGL_NO_DISPLAY)
    return fail("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA) failed");
  EGLint major = 0, minor = 0;
  if (!eglInitialize(gl->display_, &major, &minor)) {
    gl->display_ = EGL_NO_DISPLAY;
    return fail("eglInitialize failed");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(EGL_OPENGL_API) failed");
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               4,
                               EGL_CONTEXT_MINOR_VERSION,
                               5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_CONTEXT_OPENGL_DEBUG,
                               options.debug ? EGL_TRUE : EGL_FALSE,
                               EGL_NONE};
  gl->context_ = eglCreateContext(gl->display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (gl->context_ == EGL_NO_CONTEXT) return fail("eglCreateContext (OpenGL 4.5 core) failed");
  if (!gl->make_current()) return fail("eglMakeCurrent failed");
  auto text = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s ? s : "");
  };
  gl->renderer = text(GL_RENDERER);
  gl->version = text(GL_VERSION);
  if (options.require_llvmpipe && gl->renderer.find("llvmpipe") == std::string::npos)
    return fail("the renderer is '" + gl->renderer + "', not Mesa's llvmpipe");
  if (options.debug) {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);  // the message arrives inside the call that caused it
    glDebugMessageCallback(&GlContext::on_message, gl.get());
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  }
  return gl;
}

GlContext::~GlContext() {
  if (display_ == EGL_NO_DISPLAY) return;
  if (context_ != EGL_NO_CONTEXT) {
    if (eglGetCurrentContext() == context_) {
      glDebugMessageCallback(nullptr, nullptr);
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    eglDestroyContext(display_, context_);
  }
  eglTerminate(display_);
}

bool GlContext::make_current() const {
  return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE;
}

bool GlContext::release_current() const {
  return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT) == EGL_TRUE;
}

std::vector<std::string> GlContext::error_messages() const {
  std::lock_guard lock(mutex_);
  return messages_;
}

void GlContext::clear_messages() {
  std::lock_guard lock(mutex_);
  messages_.clear();
}

void GLAPIENTRY GlContext::on_message(GLenum, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                      const GLchar* message, const void* user) {
  if (type != GL_DEBUG_TYPE_ERROR && severity != GL_DEBUG_SEVERITY_HIGH) return;
  auto* self = static_cast<GlContext*>(const_cast<void*>(user));
  std::string text = length >= 0 ? std::string(message, size_t(length)) : std::string(message);
  std::lock_guard lock(self->mutex_);
  self->messages_.push_back(self->renderer + ": GL debug " + type_name(type) + " (id " + std::to_string(id) +
                            "): " + text);
}

}  // namespace statepack::bootstrap
