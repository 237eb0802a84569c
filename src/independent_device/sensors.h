#pragma once
// Sensors as real rigs give them.
//  * IMU pair (two BNO055, paper Sec. "Exosuit Prototype"): fused orientation at 100 Hz, Euler output with 16 LSB
//    per degree (BNO055 data sheet, BST-BNO055-DS000, Table 3-29: 1/16 deg). Relative angle noise: AR(1) (first
//    order Gauss-Markov) with 0.08 deg s.d. and 0.3 s correlation (the fusion filter's low-pass shapes the
//    accelerometer noise; static BNO055 orientation noise of ~0.1 deg is typical of bench reports), plus slow drift:
//    a per-trial rate (s.d. 0.01 deg/s) and a random walk (0.03 deg/sqrt(s)) of the gyro-bias estimate.
//    The angles are computed in the forearm IMU's frame and zeroed at the start of each trial (raw - raw at start,
//    both on the 1/16 deg grid, so the logged angle is on the grid).
//    imu_bias forms: the forearm IMU rolled about the forearm's axis (the forearm is round: the rotation axes seen
//    by the sensors are tilted, coupling FE into UR and shrinking FE by cos(gamma)); fusion-output latency with
//    sample-to-sample jitter.
//  * Pressure monitor: QB3 analog monitor read by the Arduino ADC: noise s.d. 0.15 kPa (10-bit ADC over 137 kPa
//    is 0.13 kPa/LSB; QB3 accuracy +-0.5 % FS), logged at 0.1 kPa.
//  * Load cells: ATI Mini45 torque (logged at 0.001 N m, s.d. 0.006 N m of a 1 s average) and the tensile tester's
//    S-beam cell (0.3 N s.d., logged at 0.1 N).

#include <array>
#include <cstdint>
#include <deque>

#include "independent_device/random.h"

namespace softwrist::independent {

struct ImuSpec {
  double resolution_deg = 0.0625;
  double sample_period_s = 0.01;
  double noise_sd_deg = 0.08;
  double noise_correlation_s = 0.3;
  double drift_rate_sd_deg_per_s = 0.01;
  double random_walk_deg_per_sqrt_s = 0.03;
  // imu_bias forms
  double roll_misalignment_rad = 0.0;
  double latency_s = 0.0, latency_jitter_s = 0.0;
};

class ImuPair {
 public:
  // noisy = false: an ideal sensor (no noise, drift or quantisation) for the noise-free reference run.
  ImuPair(const ImuSpec& spec, std::uint64_t seed, std::uint64_t trial, bool noisy);
  // The true wrist angles at time t (called every simulation step, before sample()).
  void observe(double t_s, double fe_rad, double ur_rad);
  // A fusion output at time t.
  void sample(double t_s);
  // Zeroes the angles at the last sample.
  void zero();
  double fe_deg() const { return raw_[0] - offset_[0]; }
  double ur_deg() const { return raw_[1] - offset_[1]; }

 private:
  std::array<double, 2> truth_at(double t_s) const;

  ImuSpec spec_;
  bool noisy_;
  Rng noise_, jitter_;
  std::deque<std::array<double, 3>> history_;
  std::array<double, 2> ar_{}, drift_{}, rate_{};
  double last_sample_s_ = 0.0;
  bool sampled_ = false;
  std::array<double, 2> raw_{}, offset_{};
};

// One reading of a QB3 pressure monitor [kPa]; rng == nullptr: ideal.
double read_pressure_monitor_kpa(double monitor_kpa, Rng* rng);
// A torque-sensor reading [N m] and a tensile load-cell reading [N]; rng == nullptr: ideal.
double read_torque_sensor_nm(double torque_nm, Rng* rng);
double read_tensile_load_cell_n(double force_n, Rng* rng);

}  // namespace softwrist::independent
