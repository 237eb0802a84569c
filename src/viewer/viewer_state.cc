#include "viewer/viewer_state.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "physics/units.h"

namespace softwrist::viewer {

std::optional<KeyCommand> command_for_key(int key, int mods) {
  const bool fine = (mods & GLFW_MOD_SHIFT) != 0;
  if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) return KeyCommand{Command::kSelect, key - GLFW_KEY_1};
  switch (key) {
    case GLFW_KEY_UP:
      return KeyCommand{fine ? Command::kRaiseFinely : Command::kRaise};
    case GLFW_KEY_DOWN:
      return KeyCommand{fine ? Command::kLowerFinely : Command::kLower};
    case GLFW_KEY_0:
      return KeyCommand{Command::kVentAll};
    case GLFW_KEY_SPACE:
      return KeyCommand{Command::kTogglePause};
    case GLFW_KEY_BACKSPACE:
      return KeyCommand{Command::kReset};
    case GLFW_KEY_V:
      return KeyCommand{Command::kNextCamera};
    default:
      return std::nullopt;
  }
}

std::vector<ActuatorRange> actuator_ranges(const mjModel* model, double default_max_kpa) {
  std::vector<ActuatorRange> ranges;
  for (int u = 0; u < model->nu; ++u) {
    const char* name = mj_id2name(model, mjOBJ_ACTUATOR, u);
    ActuatorRange range{name != nullptr ? name : fmt::format("actuator {}", u), 0.0, default_max_kpa};
    if (model->actuator_ctrllimited[u]) {
      range.low = model->actuator_ctrlrange[2 * u];
      range.high = model->actuator_ctrlrange[2 * u + 1];
    }
    ranges.push_back(range);
  }
  return ranges;
}

ViewerState::ViewerState(std::vector<ActuatorRange> actuators)
    : actuators_(std::move(actuators)), commands_kpa_(actuators_.size(), 0.0) {
  for (std::size_t i = 0; i < actuators_.size(); ++i)
    commands_kpa_[i] = std::clamp(0.0, actuators_[i].low, actuators_[i].high);
}

void ViewerState::set_command(int actuator, double pressure_kpa) {
  if (actuator < 0 || actuator >= static_cast<int>(actuators_.size())) {
    throw std::out_of_range(fmt::format("the model has no actuator {}", actuator + 1));
  }
  const ActuatorRange& r = actuators_[static_cast<std::size_t>(actuator)];
  commands_kpa_[static_cast<std::size_t>(actuator)] = std::clamp(pressure_kpa, r.low, r.high);
}

bool ViewerState::apply(const KeyCommand& command) {
  const auto step = [&](double fraction) {
    if (actuators_.empty()) return;
    const ActuatorRange& r = actuators_[static_cast<std::size_t>(selected_)];
    set_command(selected_, commands_kpa_[static_cast<std::size_t>(selected_)] + fraction * (r.high - r.low));
  };
  switch (command.command) {
    case Command::kSelect:
      if (command.actuator >= 0 && command.actuator < static_cast<int>(actuators_.size())) selected_ = command.actuator;
      break;
    case Command::kRaise:
      step(0.1);
      break;
    case Command::kLower:
      step(-0.1);
      break;
    case Command::kRaiseFinely:
      step(0.01);
      break;
    case Command::kLowerFinely:
      step(-0.01);
      break;
    case Command::kVentAll:
      for (std::size_t i = 0; i < actuators_.size(); ++i) set_command(static_cast<int>(i), 0.0);
      break;
    case Command::kTogglePause:
      paused_ = !paused_;
      break;
    case Command::kReset:
      for (std::size_t i = 0; i < actuators_.size(); ++i) set_command(static_cast<int>(i), 0.0);
      paused_ = false;
      return true;
    case Command::kNextCamera:
      camera_ = camera_ == CameraMode::kRadial
                    ? CameraMode::kPalmar
                    : (camera_ == CameraMode::kPalmar ? CameraMode::kFree : CameraMode::kRadial);
      break;
  }
  return false;
}

std::vector<std::pair<std::string, std::string>> ViewerState::overlay(const mjModel* model, const mjData* data) const {
  static constexpr const char* kCameraNames[] = {"radial view", "palmar view", "free camera"};
  std::vector<std::pair<std::string, std::string>> rows;
  rows.emplace_back("time", fmt::format("{:.2f} s{}, {}", data->time, paused_ ? " (paused)" : "",
                                        kCameraNames[static_cast<int>(camera_)]));
  for (int j = 0; j < model->njnt; ++j) {
    if (model->jnt_type[j] != mjJNT_HINGE) continue;
    const char* name = mj_id2name(model, mjOBJ_JOINT, j);
    rows.emplace_back(
        name != nullptr ? name : fmt::format("joint {}", j),
        fmt::format("{:6.1f} deg, muscle torque {:+6.3f} N m", units::rad_to_deg(data->qpos[model->jnt_qposadr[j]]),
                    data->qfrc_actuator[model->jnt_dofadr[j]]));
  }
  for (int u = 0; u < model->nu && u < static_cast<int>(actuators_.size()); ++u) {
    const int act = u - (model->nu - model->na);  // activations belong to the last na actuators
    const std::string regulated = act >= 0 ? fmt::format(", regulated {:5.1f}", data->act[act]) : "";
    // On a tendon an fPAM pulls (force <= 0); on its own joint (routing planar, sim/device.h) its force is its
    // torque in its own direction.
    const bool on_joint = model->actuator_trntype[u] == mjTRN_JOINT;
    const std::string effort = on_joint ? fmt::format("torque {:5.2f} N m", data->actuator_force[u])
                                        : fmt::format("pull {:5.1f} N", std::max(0.0, -data->actuator_force[u]));
    rows.emplace_back(
        fmt::format("{}{} {}", u == selected_ ? "> " : "  ", u + 1, actuators_[static_cast<std::size_t>(u)].name),
        fmt::format("command {:5.1f}{} kPa, {}", commands_kpa_[static_cast<std::size_t>(u)], regulated, effort));
  }
  return rows;
}

}  // namespace softwrist::viewer
