#include "physics/range_of_motion.h"

#include <numbers>

#include "physics/errors.h"

namespace softwrist::physics {

std::optional<double> joint_limit(const Muscle& muscle, double pressure, double max_angle) {
  require(max_angle > 0.0 && max_angle <= std::numbers::pi, "max_angle [rad]", max_angle, "must lie in (0, pi]");
  const auto pulls = [&](double angle) { return muscle_state(muscle, angle, pressure).torque > 0.0; };
  if (!pulls(0.0)) return 0.0;
  constexpr double kScanStep = 0.5 * std::numbers::pi / 180.0;
  double below = 0.0;
  for (double angle = kScanStep; below < max_angle; angle += kScanStep) {
    const double above = angle < max_angle ? angle : max_angle;
    if (!pulls(above)) {
      double lo = below, hi = above;
      while (hi - lo > 1e-10) {
        const double mid = 0.5 * (lo + hi);
        (pulls(mid) ? lo : hi) = mid;
      }
      return hi;
    }
    below = above;
  }
  return std::nullopt;
}

}  // namespace softwrist::physics
