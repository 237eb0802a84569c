#pragma once
// A model-based controller for the exosuit (the Discussion's way forward: "adding a model-based feed forward term"
// and a nonlinear PID in place of the constant-gain pressure feedback). Per axis, every period:
//
//  1. Reference shaping: the desired angle, clamped into the range the exosuit can hold (physics::reachable_range,
//     less a margin; a clamped target is reported unreachable), passes a critically damped second-order filter of
//     bandwidth w driven by the desired angle and rate. A step becomes a smooth move without overshoot (10-90 %
//     rise time 3.36 / w); a smooth trajectory passes with little lag.
//  2. Feedforward: the muscles must cancel the relaxed wrist's stiffness and the hand's weight at the reference
//     angle, looked ahead by the regulators' lag (angle r + lead * dr/dt).
//  3. Feedback: PID on the IMU angle in torque units [N m], with the derivative on a low-passed velocity estimate
//     from the IMU samples, and the integral frozen while the pair is saturated in the error's direction (no
//     wind-up).
//  4. Allocation: the torque demand becomes the pair's pressures through the torque model at the look-ahead angle
//     (pressure_allocation.h), with co-contraction at small demands.
//
// Because the allocation keeps pressures fixed for a given reference, the muscles' own stiffness (their torque
// falls as the wrist moves their way) holds the wrist at the reference as a spring would, and the PID only corrects
// what the model misses.

#include "control/controller.h"
#include "physics/exosuit_layout.h"
#include "physics/wrist_statics.h"

namespace softwrist::control {

struct ModelBasedParameters {
  double period_s = 0.014;                             // the paper's loop period
  double max_kpa = physics::kRegulatorMaxPressureKpa;  // regulator range
  double co_contraction_kpa = 5.0;                     // both muscles of a pair at zero demand
  double reference_bandwidth_rad_s = 6.0;              // w of the reference filter: 10-90 % in 0.56 s
  double kp_nm_per_rad = 0.5;
  double ki_nm_per_rad_s = 5.0;
  double kd_nms_per_rad = 0.02;
  double integral_limit_nm = 1.0;
  double velocity_cutoff_hz = 5.0;  // of the IMU velocity estimate
  double lead_s = 0.1;              // look-ahead of the feedforward: the regulators' time constant
  double reach_margin_deg = 1.0;    // targets are held this far inside the reachable range
};

class ModelBasedController final : public Controller {
 public:
  // `wrist` is the controller's model of the device (it need not be the plant's). Throws std::invalid_argument for
  // parameters out of range.
  ModelBasedController(physics::WristModel wrist, ModelBasedParameters parameters = {});

  std::string name() const override { return "model_based"; }
  double period_s() const override { return parameters_.period_s; }
  void reset() override;
  Pressures command(double t_s, const Reference& desired, const ImuReading& reading) override;
  AxisFlags unreachable() const override { return unreachable_; }

  const physics::ReachableRange& reachable_range() const { return range_; }
  const ModelBasedParameters& parameters() const { return parameters_; }

 private:
  struct AxisState {
    double reference = 0.0, reference_rate = 0.0;  // [rad], [rad/s]
    double last_angle = 0.0, velocity = 0.0;       // IMU angle [rad] and its filtered rate [rad/s]
    double integral = 0.0;                         // [N m]
  };
  physics::WristModel wrist_;
  ModelBasedParameters parameters_;
  physics::ReachableRange range_;
  std::array<AxisState, 2> axes_{};
  AxisFlags unreachable_{false, false};
  Pressures pressures_{};
  bool started_ = false;
  double last_t_s_ = 0.0, last_sample_s_ = 0.0;
};

}  // namespace softwrist::control
