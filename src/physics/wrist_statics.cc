#include "physics/wrist_statics.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace softwrist::physics {

double WristModel::limit(WristAxis axis, double direction) const {
  if (axis == WristAxis::kFlexionExtension) return direction > 0.0 ? flexion_limit : extension_limit;
  return direction > 0.0 ? ulnar_limit : radial_limit;
}

double WristModel::passive(WristAxis axis, double angle) const {
  return relaxed_wrist_torque(stiffness(axis), limit_stiffening, limit(axis, 1.0), limit(axis, -1.0), angle,
                              asymmetry(axis));
}

AxisTorques axis_torques(const WristModel& wrist, WristAxis axis, double angle, double agonist_pressure,
                         double antagonist_pressure) {
  const PairTorque pair = pair_torque(wrist.muscles.pair(axis), angle, agonist_pressure, antagonist_pressure);
  AxisTorques t;
  t.agonist = pair.agonist.torque;
  t.antagonist = -pair.antagonist.torque;
  t.passive = wrist.passive(axis, angle);
  if (axis == WristAxis::kUlnarRadial) t.gravity = wrist.hand_weight_moment * std::cos(angle);
  return t;
}

double settled_angle(const WristModel& wrist, WristAxis axis, double direction, double agonist_pressure,
                     double antagonist_pressure) {
  const double limit = wrist.limit(axis, direction);
  // The net torque in `direction` at a distance `s` >= 0 from neutral.
  const auto push = [&](double s) {
    return direction * axis_torques(wrist, axis, direction * s, agonist_pressure, antagonist_pressure).net();
  };
  if (push(0.0) <= 0.0) return 0.0;
  const double step = limit / 400.0;
  double lo = 0.0;
  for (int i = 1; i <= 400; ++i) {
    double hi = step * i;
    if (push(hi) <= 0.0) {
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (push(mid) > 0.0 ? lo : hi) = mid;
      }
      return direction * 0.5 * (lo + hi);
    }
    lo = hi;
  }
  return direction * limit;
}

namespace {

// The range on one axis: {towards positive angles, towards negative angles}, each positive [rad].
std::pair<double, double> extent(const ReachableRange& range, WristAxis axis) {
  return axis == WristAxis::kFlexionExtension ? std::pair{range.flexion, range.extension}
                                              : std::pair{range.ulnar, range.radial};
}

}  // namespace

bool ReachableRange::contains(WristAxis axis, double angle, double margin) const {
  const auto [positive, negative] = extent(*this, axis);
  return angle <= positive - margin && angle >= -(negative - margin);
}

double ReachableRange::clamp(WristAxis axis, double angle, double margin) const {
  const auto [positive, negative] = extent(*this, axis);
  return std::clamp(angle, std::min(-(negative - margin), 0.0), std::max(positive - margin, 0.0));
}

ReachableRange reachable_range(const WristModel& wrist, double max_pressure) {
  using enum WristAxis;
  return {.flexion = settled_angle(wrist, kFlexionExtension, 1.0, max_pressure, 0.0),
          .extension = -settled_angle(wrist, kFlexionExtension, -1.0, 0.0, max_pressure),
          .ulnar = settled_angle(wrist, kUlnarRadial, 1.0, max_pressure, 0.0),
          .radial = -settled_angle(wrist, kUlnarRadial, -1.0, 0.0, max_pressure)};
}

}  // namespace softwrist::physics
