#pragma once
// What the interactive viewer's keys change, apart from any window: which muscle is selected, each muscle's
// commanded pressure (kept within its regulator's range), pause, reset and the camera. The overlay's text is made
// here too, from the model and its state, so both are tested without a display.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <mujoco/mujoco.h>

namespace softwrist::viewer {

// What a key asks for. Keys (interactive_viewer.h): 1-9 select, Up/Down raise/lower (Shift: finely), 0 vent all,
// Space pause, Backspace reset, V next camera.
enum class Command { kSelect, kRaise, kLower, kRaiseFinely, kLowerFinely, kVentAll, kTogglePause, kReset, kNextCamera };

struct KeyCommand {
  Command command;
  int actuator = 0;  // for kSelect, 0-based
};

// The command of a GLFW key press (GLFW_KEY_* and GLFW_MOD_* values), or nullopt for keys without one.
std::optional<KeyCommand> command_for_key(int key, int mods);

enum class CameraMode { kRadial, kPalmar, kFree };

struct ActuatorRange {
  std::string name;
  double low = 0.0, high = 0.0;  // [kPa] the regulator's command range (the actuator's ctrlrange)
};

// The actuators of a model with their command ranges: ctrlrange where the actuator is ctrllimited, else 0 to
// `default_max_kpa` (the paper's 137 kPa regulators).
std::vector<ActuatorRange> actuator_ranges(const mjModel* model, double default_max_kpa);

class ViewerState {
 public:
  explicit ViewerState(std::vector<ActuatorRange> actuators);

  // Applies a command. Selecting an actuator the model does not have is ignored. Raise/lower step by a tenth of the
  // range (finely: a hundredth), clamped to it. Returns true when the simulation must be reset (kReset).
  bool apply(const KeyCommand& command);
  // Sets one command directly (the --pressures-kpa option), clamped to its range.
  void set_command(int actuator, double pressure_kpa);

  const std::vector<double>& commands_kpa() const { return commands_kpa_; }
  int selected() const { return selected_; }
  bool paused() const { return paused_; }
  CameraMode camera() const { return camera_; }
  const std::vector<ActuatorRange>& actuators() const { return actuators_; }

  // Overlay rows {label, value}: time and status, each hinge joint's angle [deg] and the muscles' torque on it
  // [N m], each actuator's commanded and regulated pressure [kPa] and pull [N] (the selected one marked ">").
  std::vector<std::pair<std::string, std::string>> overlay(const mjModel* model, const mjData* data) const;

 private:
  std::vector<ActuatorRange> actuators_;
  std::vector<double> commands_kpa_;
  int selected_ = 0;
  bool paused_ = false;
  CameraMode camera_ = CameraMode::kRadial;
};

}  // namespace softwrist::viewer
