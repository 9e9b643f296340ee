#include "farfield/gpu/window.hpp"

#include <algorithm>

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>

#include <string>

namespace farfield::gpu {

namespace {

std::string last_glfw_error() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "unknown GLFW error";
}

}  // namespace

Result<std::unique_ptr<Window>> Window::create(int width, int height, const std::string& title) {
  if (!glfwInit())
    return make_error("cannot open a window: ", last_glfw_error(),
                      " (is DISPLAY set? under no display, run through xvfb-run)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 0);
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window) {
    std::string why = last_glfw_error();
    glfwTerminate();
    return make_error("cannot create an OpenGL 4.5 core window: ", why);
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(0);  // measure frames, not the display's refresh
  return std::unique_ptr<Window>(new Window(window));
}

Window::~Window() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

void Window::make_current() {
  glfwMakeContextCurrent(window_);
}
bool Window::should_close() const {
  return glfwWindowShouldClose(window_);
}
void Window::close() {
  glfwSetWindowShouldClose(window_, GLFW_TRUE);
}
void Window::swap_buffers() {
  glfwSwapBuffers(window_);
}
void Window::poll_events() {
  glfwPollEvents();
}
bool Window::key_down(int key) const {
  return glfwGetKey(window_, key) == GLFW_PRESS;
}
void Window::framebuffer_size(int& width, int& height) const {
  glfwGetFramebufferSize(window_, &width, &height);
}
bool Window::mouse_down(int button) const {
  return glfwGetMouseButton(window_, button) == GLFW_PRESS;
}
glm::ivec2 Window::cursor_pixel() const {
  double x = 0, y = 0;
  glfwGetCursorPos(window_, &x, &y);
  int window_w = 1, window_h = 1, w = 1, h = 1;
  glfwGetWindowSize(window_, &window_w, &window_h);
  glfwGetFramebufferSize(window_, &w, &h);
  // Screen coordinates to framebuffer pixels (they differ on high-density displays).
  return {int(x * w / std::max(window_w, 1)), int(y * h / std::max(window_h, 1))};
}

}  // namespace farfield::gpu
