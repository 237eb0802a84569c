#include "control/model_based_controller.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "control/pressure_allocation.h"
#include "physics/units.h"

namespace softwrist::control {
namespace {

using physics::WristAxis;
constexpr std::array<WristAxis, 2> kAxes = {WristAxis::kFlexionExtension, WristAxis::kUlnarRadial};

double angle_deg(const WristAngles& a, int axis) { return axis == 0 ? a.fe_deg : a.ur_deg; }

}  // namespace

ModelBasedController::ModelBasedController(physics::WristModel wrist, ModelBasedParameters parameters)
    : wrist_(std::move(wrist)), parameters_(parameters) {
  const auto& p = parameters_;
  const bool ok = p.period_s > 0.0 && p.max_kpa > 0.0 && p.co_contraction_kpa >= 0.0 &&
                  p.co_contraction_kpa < p.max_kpa && p.reference_bandwidth_rad_s > 0.0 && p.kp_nm_per_rad >= 0.0 &&
                  p.ki_nm_per_rad_s >= 0.0 && p.kd_nms_per_rad >= 0.0 && p.integral_limit_nm >= 0.0 &&
                  p.velocity_cutoff_hz > 0.0 && p.lead_s >= 0.0 && p.reach_margin_deg >= 0.0;
  if (!ok) {
    throw std::invalid_argument(
        "model-based controller: needs period, bandwidth, velocity cutoff > 0; gains, limits, lead, margin >= 0; "
        "0 <= co-contraction < max pressure");
  }
  range_ = physics::reachable_range(wrist_, units::kpa_to_pa(p.max_kpa));
  reset();
}

void ModelBasedController::reset() {
  axes_ = {};
  unreachable_ = {false, false};
  pressures_.fill(parameters_.co_contraction_kpa);
  started_ = false;
}

Pressures ModelBasedController::command(double t_s, const Reference& desired, const ImuReading& reading) {
  const auto& p = parameters_;
  if (!reading.valid || !std::isfinite(reading.angles.fe_deg) || !std::isfinite(reading.angles.ur_deg) ||
      !std::isfinite(desired.angles.fe_deg) || !std::isfinite(desired.angles.ur_deg) ||
      !std::isfinite(desired.rate_deg_s.fe_deg) || !std::isfinite(desired.rate_deg_s.ur_deg) || !std::isfinite(t_s)) {
    return pressures_;  // hold: no information to act on
  }
  const bool first = !started_;
  const double dt = first ? p.period_s : std::clamp(t_s - last_t_s_, 0.0, 10.0 * p.period_s);
  const bool new_sample = first || reading.time_s > last_sample_s_;
  const double sample_dt = reading.time_s - last_sample_s_;
  const double max_pressure = units::kpa_to_pa(p.max_kpa);
  const double margin = units::deg_to_rad(p.reach_margin_deg);
  const double w = p.reference_bandwidth_rad_s;

  for (int i = 0; i < 2; ++i) {
    AxisState& s = axes_[static_cast<std::size_t>(i)];
    const WristAxis axis = kAxes[static_cast<std::size_t>(i)];
    const double measured = units::deg_to_rad(angle_deg(reading.angles, i));
    // 1. Reference shaping within the reachable range.
    const double wanted = units::deg_to_rad(angle_deg(desired.angles, i));
    const double target = range_.clamp(axis, wanted, margin);
    unreachable_[static_cast<std::size_t>(i)] = std::abs(target - wanted) > 1e-9;
    if (first) {
      s.reference = measured;
      s.last_angle = measured;
    }
    // The desired rate enters too, so that a smooth trajectory passes with an error of order (omega / w)^2
    // instead of lagging by 2 omega / w; at the range's edge the target stands still.
    const double target_rate =
        unreachable_[static_cast<std::size_t>(i)] ? 0.0 : units::deg_to_rad(angle_deg(desired.rate_deg_s, i));
    const double acceleration = w * w * (target - s.reference) + 2.0 * w * (target_rate - s.reference_rate);
    s.reference_rate += acceleration * dt;
    s.reference += s.reference_rate * dt;
    // Velocity from new IMU samples only (the loop runs at 71 Hz, the IMUs at 100 Hz).
    if (new_sample && !first && sample_dt > 0.0) {
      const double raw = (measured - s.last_angle) / sample_dt;
      const double alpha = 1.0 - std::exp(-2.0 * std::numbers::pi * p.velocity_cutoff_hz * sample_dt);
      s.velocity += alpha * (raw - s.velocity);
      s.last_angle = measured;
    }
    // 2. Feedforward at the look-ahead angle, 3. feedback, 4. allocation.
    const double ahead = s.reference + p.lead_s * s.reference_rate;
    const physics::AxisTorques relaxed = physics::axis_torques(wrist_, axis, ahead, 0.0, 0.0);
    const double feedforward = -(relaxed.passive + relaxed.gravity);
    const double error = s.reference - measured;
    const double feedback = p.kp_nm_per_rad * error + s.integral + p.kd_nms_per_rad * (s.reference_rate - s.velocity);
    const PairPressures pair = allocate_pair_pressures(wrist_, axis, ahead, feedforward + feedback,
                                                       units::kpa_to_pa(p.co_contraction_kpa), max_pressure);
    const bool pushing_into_saturation = (pair.saturated > 0 && error > 0.0) || (pair.saturated < 0 && error < 0.0);
    if (!pushing_into_saturation) {
      s.integral = std::clamp(s.integral + p.ki_nm_per_rad_s * error * dt, -p.integral_limit_nm, p.integral_limit_nm);
    }
    pressures_[static_cast<std::size_t>(2 * i)] = units::pa_to_kpa(pair.agonist);
    pressures_[static_cast<std::size_t>(2 * i + 1)] = units::pa_to_kpa(pair.antagonist);
  }
  started_ = true;
  last_t_s_ = t_s;
  if (new_sample) last_sample_s_ = reading.time_s;
  return pressures_;
}

}  // namespace softwrist::control
