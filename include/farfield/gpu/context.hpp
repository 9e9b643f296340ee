// OpenGL 4.5 core contexts: headless through EGL (device enumeration first, then Mesa's
// surfaceless platform), or a GLFW window. Functions are loaded through libepoxy. A context
// is current on the thread that created it.
#pragma once

#include <memory>
#include <string>

#include "farfield/core/result.hpp"

namespace farfield::gpu {

class Context {
 public:
  virtual ~Context() = default;
  virtual void make_current() = 0;
  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" or "NVIDIA H100 ...".
  std::string renderer_name() const;
  std::string version_string() const;
};

// Headless: no window; draw into a gpu::RenderTarget. Fails with a message naming what is
// missing (no EGL display, no GL 4.5 core context).
Result<std::unique_ptr<Context>> create_headless_context();

}  // namespace farfield::gpu
