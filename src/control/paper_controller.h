#pragma once
// The paper's antagonistic feedback controller (Section Control system, Fig. Control), exactly: every 0.014 s the
// angle error of each axis, times the gain 0.0083 kPa/deg, is added to the pressure of the muscle that moves the
// wrist towards the desired angle (the agonist for that error) and subtracted from its antagonist's; the
// antagonist's pressure falls twice as fast while it is above 13.8 kPa; all muscles start at 13.8 kPa; pressures
// stay within the regulators' range. Pure: no plant, no clock.

#include "control/controller.h"
#include "physics/exosuit_layout.h"

namespace softwrist::control {

struct PaperControllerParameters {
  double period_s = 0.014;           // control loop time step
  double gain_kpa_per_deg = 0.0083;  // G
  double initial_kpa = 13.8;         // initial pressure of every muscle, also the fast-release threshold
  double release_factor = 2.0;       // "decrease twice as fast" above the threshold
  double max_kpa = physics::kRegulatorMaxPressureKpa;  // regulator range
};

class PaperController final : public Controller {
 public:
  explicit PaperController(PaperControllerParameters parameters = {});
  std::string name() const override { return "paper"; }
  double period_s() const override { return parameters_.period_s; }
  // Back to the initial pressures.
  void reset() override;
  // Controller: update() on a valid reading; an invalid one holds the pressures.
  Pressures command(double t_s, const Reference& desired, const ImuReading& reading) override;
  // One loop iteration: the new commanded pressures [kPa] from the desired and measured angles.
  const Pressures& update(const WristAngles& desired, const WristAngles& measured);
  const Pressures& pressures() const { return pressures_; }
  const PaperControllerParameters& parameters() const { return parameters_; }

 private:
  PaperControllerParameters parameters_;
  Pressures pressures_{};
};

}  // namespace softwrist::control
