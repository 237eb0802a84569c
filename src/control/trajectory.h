#pragma once
// Desired wrist trajectories of Section Control and Demonstration, in degrees (flexion, ulnar positive) against
// time from the start of the run.

#include <memory>
#include <vector>

#include "control/plant.h"

namespace softwrist::control {

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual WristAngles at(double t_s) const = 0;
  // d/dt of at() [deg/s]; 0 at a jump.
  virtual WristAngles rate_at(double t_s) const = 0;
  Reference reference_at(double t_s) const { return {.angles = at(t_s), .rate_deg_s = rate_at(t_s)}; }
  virtual double duration_s() const = 0;
};

// Section Planar angle tracking: the desired angles jump from level to level and stay `hold_s` at each.
class StepTrajectory final : public Trajectory {
 public:
  // Throws std::invalid_argument for no levels, a non-finite level or hold_s <= 0.
  StepTrajectory(std::vector<WristAngles> levels, double hold_s);
  WristAngles at(double t_s) const override;
  WristAngles rate_at(double) const override { return {}; }
  double duration_s() const override { return hold_s_ * static_cast<double>(levels_.size()); }
  const std::vector<WristAngles>& levels() const { return levels_; }
  double hold_s() const { return hold_s_; }

 private:
  std::vector<WristAngles> levels_;
  double hold_s_;
};

// Section Spatial trajectory tracking: each axis a sinusoid between its limits, the same period, ulnar/radial
// lagging flexion/extension by `phase_lag_deg`:
//   fe(t) = mid_fe + amp_fe sin(2 pi t / T),  ur(t) = mid_ur + amp_ur sin(2 pi t / T - phase).
struct SinusoidParameters {
  double fe_min_deg = -40.0, fe_max_deg = 30.0;
  double ur_min_deg = -10.0, ur_max_deg = 30.0;
  double period_s = 24.0;
  double phase_lag_deg = 90.0;
  double periods = 3.0;
};

class SinusoidTrajectory final : public Trajectory {
 public:
  // Throws std::invalid_argument for min > max, non-finite limits, period or periods <= 0.
  explicit SinusoidTrajectory(SinusoidParameters parameters);
  WristAngles at(double t_s) const override;
  WristAngles rate_at(double t_s) const override;
  double duration_s() const override { return parameters_.period_s * parameters_.periods; }

 private:
  SinusoidParameters parameters_;
};

}  // namespace softwrist::control
