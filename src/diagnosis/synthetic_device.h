#pragma once
// A simulated exosuit standing in for a real one: it runs the paper's measurements (torque sweep, range of motion,
// tensile test, a trajectory) on the MuJoCo model of a "real" device description, with effects the nominal model may
// lack, measurement noise, and writes them as trial logs. The diagnosis's tests and benchmark hand these logs to
// `diagnose` without saying what was injected.
//
// The effects are implemented here on their own, not through diagnosis/effects.h: the real device's description is
// edited (mount stiffness, fPAM, wrist radius, relaxed wrist, regulator), commands are delayed by the dead time on
// their way to the MuJoCo model, the IMU pair samples at 100 Hz with latency, offset and noise, and the tensile rig's
// hysteresis is a loading/unloading force factor.

#include <cstdint>
#include <filesystem>

#include "sim/device.h"

namespace softwrist::diagnosis {

struct SyntheticDevice {
  sim::DeviceDescription device;  // the "real" device
  double regulator_dead_time = 0.0;  // [s]
  double imu_offset_fe_deg = 0.0, imu_offset_ur_deg = 0.0;
  double imu_latency = 0.0;  // [s]
  double hysteresis = 0.0;   // tensile force x (1 +- h)
};

struct SyntheticNoise {
  double torque_nm = 0.02;       // torque sensor (as experiments/torque_validation.json)
  double angle_jitter_deg = 1.0; // the held wrist's actual angle
  double rom_deg = 0.5;          // motion capture
  double force_n = 0.5;          // tensile rig load cell
  double imu_deg = 0.2;          // IMU pair (as the tracking experiments)
  // Regulator monitor output. Assumed: the QB3's stated accuracy is +-0.5 % of its 137 kPa span (0.7 kPa); taken
  // as a bias-free 0.3 kPa standard deviation.
  double pressure_kpa = 0.3;
};

struct SyntheticPlan {
  bool torque_sweep = true, range_of_motion = true, tensile = true, trajectory = true;
  bool measured_pressures = true;  // the trajectory logs p_<muscle>_kpa as the bridge does
  int repetitions = 3;             // sweeps, range of motion; tensile cycles
  double trajectory_s = 24.0;      // one 24 s period of antagonistic pressure sinusoids on both axes
  SyntheticNoise noise;
  std::uint64_t seed = 1;
};

// Writes torque_sweep/, range_of_motion/, tensile/ and trajectory/ (each a trials.csv + trials.json) under `out`.
// The sweep: the flexor at the eight angles and five pressures of experiments/torque_validation.json.
void write_synthetic_data(const SyntheticDevice& real, const SyntheticPlan& plan, const std::filesystem::path& out);

}  // namespace softwrist::diagnosis
