// The consumer project's OpenGL application, built against an installed statepack (find_package): it
// makes a headless OpenGL 4.5 context (EGL surfaceless, as on a machine without a display), loads the
// archive its build packed with OPENGL and links the compute program, so the installed statepack::gl,
// its header and libepoxy are proven to link and work together.
// Usage: consumer_gl_app <archive.spk>
#include <epoxy/egl.h>
#include <epoxy/gl.h>  // the application calls GL itself; statepack's header needs no GL header
#include <statepack/gl_dearchiver.hpp>

#include <cstdio>
#include <string>

namespace {

int fail(const char* what, const std::string& why) {
  std::fprintf(stderr, "consumer_gl_app: %s: %s\n", what, why.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return fail("usage", "consumer_gl_app <archive.spk>");
  auto archive = statepack::Archive::from_file(argv[1]);
  if (!archive) return fail(argv[1], archive.error().message);

  EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor) || !eglBindAPI(EGL_OPENGL_API))
    return fail("EGL", "no surfaceless display");
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               4,
                               EGL_CONTEXT_MINOR_VERSION,
                               5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
    return fail("EGL", "no OpenGL 4.5 core context");

  int status = 0;
  {
    auto dearchiver = statepack::gl::Dearchiver::create();
    if (!dearchiver) return fail("gl::Dearchiver::create", dearchiver.error().message);
    if (auto added = dearchiver->add_archive(std::move(*archive)); !added)
      return fail("add_archive", added.error().message);
    auto program = dearchiver->unpack_compute("Consumer PSO");
    if (program)
      std::printf("unpacked 'Consumer PSO' on OpenGL: program %u\n", (*program)->program);
    else
      status = fail("unpack_compute", program.error().message);
  }  // the programs go while the context is current
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display, context);
  eglTerminate(display);
  return status;
}
