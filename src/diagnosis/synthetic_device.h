#pragma once
// A simulated exosuit standing in for a real one: it runs the paper's measurements (torque sweep, range of motion,
// tensile test, a trajectory) on the MuJoCo model of a "real" device description, with effects the nominal model may
// lack, measurement noise, and writes them as trial logs. The diagnosis's tests and benchmark hand these logs to
// `diagnose` without saying what was injected.
//
// The effects are implemented here on their own, not through diagnosis/effects.h, and several in another functional
// form than the catalogue fits (diagnosis/benchmark.cc chooses them): the real device's description is edited (mount
// stiffness and stretch law, the fPAM table row by row, each muscle's wrist radius, each axis's relaxed wrist,
// the regulator), commands are delayed by the dead time and may pass a second regulator stage on their way to the
// MuJoCo model, the IMU pair samples at 100 Hz with latency (optionally jittered), offset and noise, the tensile
// rig's hysteresis is a loading/unloading force factor plus a friction force, and the muscles may rub where they
// cross the wrist (MuJoCo tendon friction, an effect outside the catalogue).

#include <cstdint>
#include <filesystem>

#include "sim/device.h"

namespace softwrist::diagnosis {

struct SyntheticDevice {
  sim::DeviceDescription device;     // the "real" device
  double regulator_dead_time = 0.0;  // [s]
  // [s] a first-order stage before the model's own regulator (0: none): the pair is a second-order regulator.
  double regulator_prefilter_time_constant = 0.0;
  double imu_offset_fe_deg = 0.0, imu_offset_ur_deg = 0.0;
  double imu_latency = 0.0;         // [s]
  double imu_latency_jitter = 0.0;  // [s] each IMU reading is late by latency + U(-jitter, +jitter)
  double imu_axis_roll_deg = 0.0;   // the IMU pair's axes turned about the forearm (ModelVariant::imu_axis_roll)
  double hysteresis = 0.0;          // tensile force x (1 +- h); in MuJoCo the fabric's hysteresis state, fraction h
  // Tensile force +- this fraction of the force at zero contraction at the same pressure (a friction that grows with
  // pressure rather than with the force).
  double hysteresis_friction = 0.0;
  double wrap_friction_n = 0.0;  // [N] dry friction of each muscle's path over the wrist (tendon frictionloss)
};

struct SyntheticNoise {
  double torque_nm = 0.02;        // torque sensor (as experiments/torque_validation.json)
  double angle_jitter_deg = 1.0;  // the held wrist's actual angle
  double rom_deg = 0.5;           // motion capture
  double force_n = 0.5;           // tensile rig load cell
  double imu_deg = 0.2;           // IMU pair (as the tracking experiments)
  // Regulator monitor output. Assumed: the QB3's stated accuracy is +-0.5 % of its 137 kPa span (0.7 kPa); taken
  // as a bias-free 0.3 kPa standard deviation.
  double pressure_kpa = 0.3;
};

struct SyntheticPlan {
  bool torque_sweep = true, range_of_motion = true, tensile = true, trajectory = true;
  bool measured_pressures = true;  // the trajectory logs p_<muscle>_kpa as the bridge does
  int repetitions = 3;             // sweeps, range of motion; tensile cycles
  double trajectory_s = 24.0;      // two 12 s periods of antagonistic pressure sinusoids on both axes
  // Or antagonistic pressure steps on both axes, a new level every 1.5 s: the rise after a step shows a regulator's
  // response, which a slow sinusoid only shows as a lag.
  bool trajectory_steps = false;
  SyntheticNoise noise;
  std::uint64_t seed = 1;
};

// Writes torque_sweep/, range_of_motion/, tensile/ and trajectory/ (each a trials.csv + trials.json) under `out`.
// The sweep: the flexor at the eight angles and five pressures of experiments/torque_validation.json.
void write_synthetic_data(const SyntheticDevice& real, const SyntheticPlan& plan, const std::filesystem::path& out);

}  // namespace softwrist::diagnosis
