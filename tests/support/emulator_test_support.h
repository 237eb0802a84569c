#pragma once
// What the bridge's tests against the device emulator share, in simulated time (bridge_emulator_test.cc) and in
// real time (bridge_real_time_test.cc): the nominal device, the short planar experiment, a constant hold.

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bridge/bridge_plant.h"
#include "bridge_apps/device_emulator.h"
#include "experiments/experiment.h"

namespace softwrist::testing {

// The range-of-motion device exactly as modelled, the hand on the table (as the planar experiments), the regulators
// given the setpoints exactly (no PWM steps, which the simulation does not have).
inline bridge::EmulatorConfig nominal_emulator_config() {
  bridge::EmulatorConfig c;
  c.model = SOFTWRIST_SOURCE_DIR "/models/rom_device.json";
  c.gravity = 0.0;
  c.effects.pwm_steps = false;
  return c;
}

// The planar task, shortened: two controllers, steps of 10 and 20 degrees.
inline experiments::ExperimentConfig short_planar_config(const std::filesystem::path& dir) {
  const nlohmann::json json = {
      {"format", "softwrist.experiment/1"},
      {"kind", "tracking"},
      {"model", SOFTWRIST_SOURCE_DIR "/models/rom_device.json"},
      {"hand_supported", true},
      {"pairs", {"fe"}},
      {"trajectory", {{"type", "steps"}, {"levels_fe_deg", {0, -10, 10}}, {"hold_s", 3}}},
      {"controllers", {{{"name", "paper"}}, {{"name", "model_based"}}}},
      {"imu", {{"noise_std_deg", 0}, {"bias_limit_deg", 0}}},  // the emulator's IMUs have no effects either
      {"settle_s", 1},
      {"repetitions", 1}};
  return {.json = json, .base_dir = dir, .source = "short_planar.json", .name = "short_planar"};
}

inline bool has_vent(const std::vector<bridge::VentEvent>& vents, const std::string& cause) {
  return std::any_of(vents.begin(), vents.end(), [&](const bridge::VentEvent& v) { return v.cause == cause; });
}

// Drives a session with a constant command every 14 ms (the paper's loop) for `seconds`.
inline void hold(bridge::BridgePlant& plant, const control::Pressures& p, double seconds) {
  const double start = plant.time_s();
  for (double t = 0.0; t < seconds; t += 0.014) {
    plant.command_pressures_kpa(p);
    plant.wait_until(start + t + 0.014);
  }
}

}  // namespace softwrist::testing
