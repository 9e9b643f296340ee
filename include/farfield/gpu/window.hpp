// A GLFW window with an OpenGL 4.5 core context, for `farfield view`. Needs a display
// (X11; Xvfb works). The context is current on the creating thread after create().
#pragma once

#include <memory>
#include <string>

#include <glm/vec2.hpp>

#include "farfield/core/result.hpp"
#include "farfield/gpu/context.hpp"

struct GLFWwindow;

namespace farfield::gpu {

class Window final : public Context {
 public:
  static Result<std::unique_ptr<Window>> create(int width, int height, const std::string& title);
  ~Window() override;
  void make_current() override;

  bool should_close() const;
  void close();
  void swap_buffers();
  void poll_events();
  bool key_down(int glfw_key) const;
  void framebuffer_size(int& width, int& height) const;
  bool mouse_down(int glfw_button) const;
  // The cursor in framebuffer pixels from the top left.
  glm::ivec2 cursor_pixel() const;
  GLFWwindow* handle() const { return window_; }

 private:
  explicit Window(GLFWwindow* window) : window_(window) {}
  GLFWwindow* window_;
};

}  // namespace farfield::gpu
