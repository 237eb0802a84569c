#include "control/pressure_allocation.h"

#include <algorithm>

namespace softwrist::control {

PairPressures pressures_on_path(double s, double co_contraction, double max_pressure) {
  s = std::clamp(s, -1.0, 1.0);
  const double rise = co_contraction + std::abs(s) * (max_pressure - co_contraction);
  const double fall = co_contraction * (1.0 - std::abs(s));
  return s >= 0.0 ? PairPressures{.agonist = rise, .antagonist = fall}
                  : PairPressures{.agonist = fall, .antagonist = rise};
}

PairPressures allocate_pair_pressures(const physics::WristModel& wrist, physics::WristAxis axis, double angle,
                                      double torque_demand, double co_contraction, double max_pressure) {
  const auto& pair = wrist.muscles.pair(axis);
  const auto torque = [&](double s) {
    const PairPressures p = pressures_on_path(s, co_contraction, max_pressure);
    return physics::pair_torque(pair, angle, p.agonist, p.antagonist).net_torque;
  };
  // Beyond either end of the path the demand cannot be met: the nearest end, flagged.
  if (const double strongest = torque(1.0); strongest <= torque_demand) {
    PairPressures p = pressures_on_path(1.0, co_contraction, max_pressure);
    p.saturated = strongest < torque_demand ? 1 : 0;
    return p;
  }
  if (const double weakest = torque(-1.0); weakest >= torque_demand) {
    PairPressures p = pressures_on_path(-1.0, co_contraction, max_pressure);
    p.saturated = weakest > torque_demand ? -1 : 0;
    return p;
  }
  double lo = -1.0, hi = 1.0;
  for (int i = 0; i < 40; ++i) {  // 2^-40 of the path: far below a regulator's resolution
    const double mid = 0.5 * (lo + hi);
    (torque(mid) < torque_demand ? lo : hi) = mid;
  }
  return pressures_on_path(0.5 * (lo + hi), co_contraction, max_pressure);
}

}  // namespace softwrist::control
