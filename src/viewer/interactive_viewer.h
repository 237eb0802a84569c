#pragma once
// `softwrist view`: the model in a GLFW window, simulated in real time. Mouse: left drag orbits, right drag pans,
// scroll zooms (free camera). Keys: 1-9 select a muscle, Up/Down raise/lower its pressure by a tenth of the range
// (Shift: a hundredth), 0 vents all, Space pauses, Backspace resets, V switches radial view / palmar view / free
// camera, Esc closes. The overlay shows time, each joint's angle and actuator torque, and each muscle's commanded
// and regulated pressure and pull. Muscles are coloured by pressure as in the offscreen renders.

#include <filesystem>
#include <map>
#include <string>

#include "physics/exosuit_layout.h"
#include "sim/model.h"

namespace softwrist::viewer {

struct ViewerOptions {
  int width = 1200, height = 800;
  // Scripted runs (tests, screenshots): stop after this many frames (0: run until the window closes), each frame
  // then advancing a fixed 1/60 s of simulated time instead of the wall clock's.
  int frames = 0;
  std::filesystem::path screenshot;                            // PNG of the last frame
  std::map<int, double> initial_commands_kpa;                  // actuator index -> command
  double default_max_kpa = physics::kRegulatorMaxPressureKpa;  // command range of actuators without ctrlrange
};

struct ViewerSummary {
  int frames = 0;
  double simulated_s = 0.0;
  std::string final_state;  // the overlay's rows, one per line
};

// Throws std::runtime_error naming the problem: no display (run under xvfb-run for headless use), no OpenGL, an
// actuator index the model does not have.
ViewerSummary run_viewer(const sim::Model& model, const ViewerOptions& options);

}  // namespace softwrist::viewer
