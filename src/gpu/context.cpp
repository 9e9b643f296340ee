#include "farfield/gpu/context.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <string_view>
#include <vector>

#include "farfield/core/assert.hpp"

namespace farfield::gpu {

namespace {

std::string gl_string(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s ? std::string(s) : std::string();
}

std::string egl_error_name(EGLint code) {
  switch (code) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return "EGL error " + std::to_string(code);
  }
}

std::string failed(const char* call) {
  return std::string(call) + " failed (" + egl_error_name(eglGetError()) + ")";
}

class HeadlessContext final : public Context {
 public:
  HeadlessContext(EGLDisplay display, EGLContext context) : display_(display), context_(context) {}
  ~HeadlessContext() override {
    if (eglGetCurrentContext() == context_)
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    // No eglTerminate: EGL hands out one display per device and platform, shared by every
    // context of the process, so terminating it here would break the others.
  }
  void make_current() override {
    const bool ok = eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_);
    FF_ASSERT(ok, "%s", failed("eglMakeCurrent").c_str());
  }

 private:
  EGLDisplay display_;
  EGLContext context_;
};

// Initializes `display` and makes a current GL 4.5 core context on it without a surface.
// Returns the context, or EGL_NO_CONTEXT with `why` set.
EGLContext make_context(EGLDisplay display, std::string& why) {
  if (display == EGL_NO_DISPLAY) return why = failed("eglGetPlatformDisplayEXT"), EGL_NO_CONTEXT;
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return why = failed("eglInitialize"), EGL_NO_CONTEXT;
  if (!epoxy_has_egl_extension(display, "EGL_KHR_surfaceless_context"))
    return why = "no EGL_KHR_surfaceless_context", EGL_NO_CONTEXT;
  if (major * 10 + minor < 15 && !epoxy_has_egl_extension(display, "EGL_KHR_create_context"))
    return why = "EGL " + std::to_string(major) + "." + std::to_string(minor) +
                 " without EGL_KHR_create_context",
           EGL_NO_CONTEXT;
  if (!eglBindAPI(EGL_OPENGL_API))
    return why = failed("eglBindAPI(EGL_OPENGL_API)"), EGL_NO_CONTEXT;

  // Rendering goes to framebuffer objects, so the config only has to allow desktop GL.
  const EGLint config_attribs[] = {
      EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_CONFORMANT, EGL_OPENGL_BIT,
      EGL_SURFACE_TYPE,    EGL_DONT_CARE,  EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  if (!eglChooseConfig(display, config_attribs, &config, 1, &configs) || configs == 0)
    return why = "no EGL config for desktop OpenGL", EGL_NO_CONTEXT;

  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                    4,
                                    EGL_CONTEXT_MINOR_VERSION,
                                    5,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                    EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                    EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
  if (context == EGL_NO_CONTEXT)
    return why = failed("eglCreateContext (OpenGL 4.5 core)"), EGL_NO_CONTEXT;
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    why = failed("eglMakeCurrent without a surface");
    eglDestroyContext(display, context);
    return EGL_NO_CONTEXT;
  }
  if (epoxy_gl_version() < 45) {
    why = "got OpenGL " + gl_string(GL_VERSION) + ", need 4.5";
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    return EGL_NO_CONTEXT;
  }
  return context;
}

}  // namespace

std::string Context::renderer_name() const {
  return gl_string(GL_RENDERER);
}
std::string Context::version_string() const {
  return gl_string(GL_VERSION);
}

Result<std::unique_ptr<Context>> create_headless_context() {
  if (!epoxy_has_egl()) return make_error("headless OpenGL: libEGL cannot be loaded");
  if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base"))
    return make_error("headless OpenGL: EGL lacks EGL_EXT_platform_base");

  std::string tried;  // what failed, for the message
  auto note = [&](const std::string& what) { tried += (tried.empty() ? "" : "; ") + what; };
  auto attempt = [&](const std::string& what, EGLDisplay display) -> std::unique_ptr<Context> {
    std::string why;
    EGLContext context = make_context(display, why);
    if (context != EGL_NO_CONTEXT) return std::make_unique<HeadlessContext>(display, context);
    note(what + ": " + why);
    return nullptr;
  };

  // A GPU device first (the NVIDIA driver on a GPU machine), a software one (llvmpipe) after.
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration")) {
    auto is_software = [](EGLDeviceEXT device) {
      const char* ext = eglQueryDeviceStringEXT(device, EGL_EXTENSIONS);
      return ext &&
             std::string_view(ext).find("EGL_MESA_device_software") != std::string_view::npos;
    };
    EGLint count = 0;
    std::vector<EGLDeviceEXT> devices;
    if (eglQueryDevicesEXT(0, nullptr, &count) && count > 0) {
      devices.resize(size_t(count));
      if (!eglQueryDevicesEXT(count, devices.data(), &count)) count = 0;
      devices.resize(size_t(count));
    }
    if (devices.empty()) note("no EGL device");
    std::stable_partition(devices.begin(), devices.end(),
                          [&](EGLDeviceEXT device) { return !is_software(device); });
    for (size_t i = 0; i < devices.size(); ++i) {
      EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
      const std::string name =
          "EGL device " + std::to_string(i) + (is_software(devices[i]) ? " (software)" : "");
      if (auto context = attempt(name, display)) return context;
    }
  } else {
    note("no EGL_EXT_device_enumeration");
  }
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (auto context = attempt("surfaceless platform", display)) return context;
  } else {
    note("no EGL_MESA_platform_surfaceless");
  }
  return make_error("headless OpenGL 4.5 core context unavailable (", tried, ")");
}

}  // namespace farfield::gpu
