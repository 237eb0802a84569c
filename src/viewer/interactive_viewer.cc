#include "viewer/interactive_viewer.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "report/offscreen_renderer.h"
#include "report/scene_style.h"
#include "sim/wrist_sim.h"
#include "viewer/viewer_state.h"

namespace softwrist::viewer {
namespace {

// GLFW's last error, for the exception (GLFW reports through a callback).
std::string& last_glfw_error() {
  thread_local std::string error;
  return error;
}

// GLFW itself, initialized for the viewer's lifetime.
struct Glfw {
  Glfw(const Glfw&) = delete;
  Glfw& operator=(const Glfw&) = delete;
  Glfw() {
    glfwSetErrorCallback([](int, const char* description) { last_glfw_error() = description; });
    if (!glfwInit()) {
      throw std::runtime_error(
          fmt::format("view: cannot start GLFW ({}); the viewer needs a display (for headless "
                      "use run it under xvfb-run, or use `softwrist render`)",
                      last_glfw_error()));
    }
  }
  ~Glfw() { glfwTerminate(); }
};

struct WindowDeleter {
  void operator()(GLFWwindow* window) const { glfwDestroyWindow(window); }
};

// The window, the scene and the mouse, reached from GLFW's callbacks through the window's user pointer.
struct Session {
  const mjModel* model = nullptr;
  mjData* data = nullptr;
  sim::WristSim* wrist = nullptr;  // a softwrist model: steps as the experiments do
  ViewerState state;
  mjvCamera camera;
  mjvOption option;
  mjvScene scene;
  mjrContext context;
  bool left = false, right = false;
  double last_x = 0.0, last_y = 0.0;

  Session(const mjModel* m, mjData* d, ViewerState s, sim::WristSim* w)
      : model(m), data(d), wrist(w), state(std::move(s)) {
    mjv_defaultCamera(&camera);
    mjv_defaultOption(&option);
    mjv_defaultScene(&scene);
    mjr_defaultContext(&context);
    mjv_makeScene(model, &scene, 2000);
    mjr_makeContext(model, &context, mjFONTSCALE_100);  // needs the window's OpenGL context current
    apply_camera();
    reset();
  }
  ~Session() {
    mjr_freeContext(&context);
    mjv_freeScene(&scene);
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  void apply_camera() {
    if (state.camera() == CameraMode::kRadial) report::set_view_camera(report::View::kRadial, &camera);
    if (state.camera() == CameraMode::kPalmar) report::set_view_camera(report::View::kPalmar, &camera);
  }
  void reset() {
    if (wrist != nullptr) {
      wrist->reset();
      return;
    }
    mj_resetData(model, data);
    mj_forward(model, data);
  }
  // Advances `duration` [s]. A softwrist model through WristSim (the relaxed wrist's stiffening towards its limits and
  // its asymmetry, wrist surfaces that are not circles); an unstable state is reset, as MuJoCo does on its own.
  void advance(double duration) {
    if (wrist == nullptr) {
      const double end = data->time + duration;
      while (data->time < end) mj_step(model, data);
      return;
    }
    try {
      wrist->run(duration);
    } catch (const std::runtime_error&) {
      reset();
    }
  }
};

Session& session_of(GLFWwindow* window) { return *static_cast<Session*>(glfwGetWindowUserPointer(window)); }

void on_key(GLFWwindow* window, int key, int, int action, int mods) {
  if (action == GLFW_RELEASE) return;
  if (key == GLFW_KEY_ESCAPE) {
    glfwSetWindowShouldClose(window, GLFW_TRUE);
    return;
  }
  Session& s = session_of(window);
  const auto command = command_for_key(key, mods);
  if (!command) return;
  if (s.state.apply(*command)) s.reset();
  if (command->command == Command::kNextCamera) {
    if (s.state.camera() == CameraMode::kFree) s.camera.type = mjCAMERA_FREE;  // keep the current pose, free to orbit
    s.apply_camera();
  }
}

void on_button(GLFWwindow* window, int, int, int) {
  Session& s = session_of(window);
  s.left = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  s.right = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  glfwGetCursorPos(window, &s.last_x, &s.last_y);
}

// Dragging moves the camera, which frees it from the paper's views.
void on_cursor(GLFWwindow* window, double x, double y) {
  Session& s = session_of(window);
  if (!s.left && !s.right) return;
  const double dx = x - s.last_x, dy = y - s.last_y;
  s.last_x = x;
  s.last_y = y;
  int width = 0, height = 0;
  glfwGetWindowSize(window, &width, &height);
  if (height <= 0) return;
  while (s.state.camera() != CameraMode::kFree) s.state.apply({Command::kNextCamera});
  const mjtMouse action = s.right ? mjMOUSE_MOVE_V : mjMOUSE_ROTATE_V;
  mjv_moveCamera(s.model, action, dx / height, dy / height, &s.scene, &s.camera);
}

void on_scroll(GLFWwindow* window, double, double dy) {
  Session& s = session_of(window);
  while (s.state.camera() != CameraMode::kFree) s.state.apply({Command::kNextCamera});
  mjv_moveCamera(s.model, mjMOUSE_ZOOM, 0.0, -0.05 * dy, &s.scene, &s.camera);
}

std::string rows_text(const std::vector<std::pair<std::string, std::string>>& rows, bool labels) {
  std::string text;
  for (const auto& [label, value] : rows) text += (text.empty() ? "" : "\n") + (labels ? label : value);
  return text;
}

constexpr const char* kHelp =
    "1-9 select muscle   Up/Down pressure (Shift: fine)   0 vent all\n"
    "Space pause   Backspace reset   V view   drag/scroll camera   Esc quit";

}  // namespace

ViewerSummary run_viewer(const sim::Model& sim_model, const ViewerOptions& options) {
  // A softwrist model (its wrist joints) steps as the experiments do, and one that WristSim refuses is an error naming
  // why; any other MJCF steps with MuJoCo alone.
  std::optional<sim::WristSim> wrist;
  if (mj_name2id(sim_model.get(), mjOBJ_JOINT, "wrist_fe") >= 0 &&
      mj_name2id(sim_model.get(), mjOBJ_JOINT, "wrist_ur") >= 0) {
    wrist.emplace(sim_model);
  }
  const mjModel* model = wrist ? wrist->model() : sim_model.get();
  ViewerState state(actuator_ranges(model, options.default_max_kpa));
  for (const auto& [actuator, kpa] : options.initial_commands_kpa) state.set_command(actuator, kpa);

  Glfw glfw;
  glfwWindowHint(GLFW_VISIBLE, GLFW_TRUE);
  const std::unique_ptr<GLFWwindow, WindowDeleter> owned_window(
      glfwCreateWindow(options.width, options.height, "softwrist view", nullptr, nullptr));
  GLFWwindow* window = owned_window.get();
  if (window == nullptr) throw std::runtime_error(fmt::format("view: cannot open a window ({})", last_glfw_error()));
  glfwMakeContextCurrent(window);
  glfwSwapInterval(options.frames > 0 ? 0 : 1);

  const sim::Data own_data = wrist ? sim::Data{} : sim::make_data(sim_model);
  mjData* data = wrist ? wrist->data() : own_data.get();
  Session s(model, data, std::move(state), wrist ? &*wrist : nullptr);  // freed before the window (declared after it)
  glfwSetWindowUserPointer(window, &s);
  glfwSetKeyCallback(window, on_key);
  glfwSetMouseButtonCallback(window, on_button);
  glfwSetCursorPosCallback(window, on_cursor);
  glfwSetScrollCallback(window, on_scroll);

  ViewerSummary summary;
  auto last = std::chrono::steady_clock::now();
  while (!glfwWindowShouldClose(window)) {
    // Advance the simulation to the wall clock (at most 1/30 s per frame, so that a slow frame does not stall the
    // viewer), or by a fixed 1/60 s per frame in scripted runs.
    const auto now = std::chrono::steady_clock::now();
    const double elapsed =
        options.frames > 0 ? 1.0 / 60.0 : std::min(std::chrono::duration<double>(now - last).count(), 1.0 / 30.0);
    last = now;
    if (!s.state.paused()) {
      for (int u = 0; u < model->nu; ++u) data->ctrl[u] = s.state.commands_kpa()[static_cast<std::size_t>(u)];
      s.advance(elapsed);
      summary.simulated_s += elapsed;
    }
    int width = 0, height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    const mjrRect viewport = {0, 0, width, height};
    mjv_updateScene(model, data, &s.option, nullptr, &s.camera, mjCAT_ALL, &s.scene);
    report::colour_muscles_by_pressure(model, data, options.default_max_kpa, &s.scene);
    mjr_render(viewport, &s.scene, &s.context);
    const auto rows = s.state.overlay(model, data);
    mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, viewport, rows_text(rows, true).c_str(), rows_text(rows, false).c_str(),
                &s.context);
    mjr_overlay(mjFONT_NORMAL, mjGRID_BOTTOMLEFT, viewport, kHelp, nullptr, &s.context);
    ++summary.frames;
    if (options.frames > 0 && summary.frames >= options.frames) {
      if (!options.screenshot.empty()) {
        mjr_setBuffer(mjFB_WINDOW, &s.context);
        report::write_png(report::read_pixels(s.context, width, height), options.screenshot);
      }
      for (const auto& [label, value] : rows) summary.final_state += label + ": " + value + "\n";
      glfwSetWindowShouldClose(window, GLFW_TRUE);
    }
    glfwSwapBuffers(window);
    glfwPollEvents();
  }
  return summary;
}

}  // namespace softwrist::viewer
