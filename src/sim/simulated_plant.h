#pragma once
// The Plant (control/plant.h) of the simulation: the MuJoCo wrist with the fPAM plugin, and an IMU pair model.
//
// IMU model (Section Exosuit Prototype and Control: two BNO055 IMUs, one on the dorsal hand and one on the dorsal
// forearm, read at 100 Hz; their relative orientation gives the two wrist angles): every `period_s` the hand's
// orientation relative to the forearm is sampled and decomposed into the flexion/extension and ulnar/radial angles
// of the model's joint order, then a fixed bias (drawn once per run within +-bias_limit_deg: the BNO055's heading
// accuracy, +-2.5 deg in its datasheet) and white noise are added. The noise level is an assumption.

#include <optional>
#include <random>

#include "control/plant.h"
#include "sim/wrist_sim.h"

namespace softwrist::sim {

struct ImuModel {
  double period_s = 0.01;       // 100 Hz
  double noise_std_deg = 0.2;   // assumed
  double bias_limit_deg = 2.5;  // BNO055 heading accuracy; 0 for an unbiased pair
  unsigned long long seed = 1;
};

// The wrist angles [rad] (flexion, ulnar positive) of a hand orientation relative to the forearm, given as the
// hand's x axis (along the hand) in the forearm frame: the inverse of the joints' rotation Ry(fe) Rz(-ur).
control::WristAngles wrist_angles_from_hand_axis(const double hand_x_in_forearm[3]);

class SimulatedPlant final : public control::Plant {
 public:
  SimulatedPlant(const Model& model, double max_pressure_kpa, ImuModel imu = {});

  void command_pressures_kpa(const control::Pressures& pressures) override;
  control::ImuReading read_angles() override { return reading_; }
  double time_s() const override { return wrist_.time(); }
  void wait_until(double t) override;
  double max_pressure_kpa() const override { return max_pressure_kpa_; }

  // The true joint angles (not what the IMUs say), for logs and checks.
  control::WristAngles true_angles() const;
  // What an ideal IMU pair would say now (relative orientation of the bodies, before bias and noise).
  control::WristAngles ideal_imu_angles();
  WristSim& wrist() { return wrist_; }
  // A subject holding the wrist still at `angles` (the paper zeroes the IMUs "at a neutral position of the wrist"):
  // while held, time passes with the joints fixed there (the regulators still fill or vent); nullopt lets go.
  void hold(std::optional<control::WristAngles> angles) { held_ = angles; }

 private:
  void sample();
  WristSim wrist_;
  double max_pressure_kpa_;
  ImuModel imu_;
  std::mt19937_64 rng_;
  control::WristAngles bias_;
  control::ImuReading reading_;
  double next_sample_ = 0.0;
  int forearm_body_ = -1, hand_body_ = -1;
  std::optional<control::WristAngles> held_;
};

}  // namespace softwrist::sim
