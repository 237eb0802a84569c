#include "independent_device/wrist_dynamics.h"

#include <cmath>

#include "independent_device/units.h"

namespace softwrist::independent {
namespace {

double axis_torque(double angle, double rest, double stiffness, double gain_positive, double gain_negative,
                   double damping, double rate, double limit_torque, double scale, double limit_positive,
                   double limit_negative, double tone) {
  const double d = angle - rest;
  double torque = -tone * stiffness * d * (d > 0.0 ? gain_positive : gain_negative) - damping * rate;
  if (limit_torque > 0.0) {
    auto stiffening = [&](double a) {
      return std::exp((a - limit_positive) / scale) - std::exp((-limit_negative - a) / scale);
    };
    torque -= tone * limit_torque * (stiffening(angle) - stiffening(0.0));
  }
  return torque;
}

}  // namespace

std::array<double, 2> passive_torque_nm(const PassiveWrist& wrist, const WristCondition& condition,
                                        const WristState& state) {
  const auto& g = wrist.direction_gain;
  const auto& lim = wrist.limit_rad;
  return {axis_torque(state.fe, condition.rest_fe_rad, wrist.stiffness_fe_nm_per_rad, g[0], g[1],
                      wrist.damping_fe_nms_per_rad, state.fe_rate, wrist.limit_torque_nm, wrist.limit_scale_rad, lim[0],
                      lim[1], condition.stiffness_scale),
          axis_torque(state.ur, condition.rest_ur_rad, wrist.stiffness_ur_nm_per_rad, g[2], g[3],
                      wrist.damping_ur_nms_per_rad, state.ur_rate, wrist.limit_torque_nm, wrist.limit_scale_rad, lim[2],
                      lim[3], condition.stiffness_scale)};
}

std::array<double, 2> gravity_torque_nm(const HandSegment& hand, Posture posture, double fe, double ur) {
  const double mgr = hand.mass_kg * kGravity * hand.com_m;
  switch (posture) {
    case Posture::gravity_fe:  // V = -m g r cos(ur) sin(fe)
      return {mgr * std::cos(ur) * std::cos(fe), -mgr * std::sin(ur) * std::sin(fe)};
    case Posture::gravity_ur:  // V = -m g r sin(ur)
      return {0.0, mgr * std::cos(ur)};
    case Posture::hand_supported:
      break;
  }
  return {0.0, 0.0};
}

void step_wrist(WristState& state, const HandSegment& hand, const std::array<double, 2>& torque_nm, double dt_s,
                bool ur_locked) {
  const double s = std::sin(state.ur), c = std::cos(state.ur);
  const double ia = hand.inertia_axial_kg_m2, ip = hand.inertia_perp_kg_m2;
  const double m11 = ia * s * s + ip * c * c;
  const double fe_acc = (torque_nm[0] - 2.0 * s * c * (ia - ip) * state.fe_rate * state.ur_rate) / m11;
  const double ur_acc = ur_locked ? 0.0 : (torque_nm[1] + s * c * (ia - ip) * state.fe_rate * state.fe_rate) / ip;
  state.fe_rate += dt_s * fe_acc;
  state.fe += dt_s * state.fe_rate;
  if (ur_locked) {
    state.ur = 0.0;
    state.ur_rate = 0.0;
  } else {
    state.ur_rate += dt_s * ur_acc;
    state.ur += dt_s * state.ur_rate;
  }
}

}  // namespace softwrist::independent
