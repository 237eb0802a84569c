#include "physics/relaxed_wrist.h"

#include <algorithm>
#include <cmath>

namespace softwrist::physics {

double limit_stiffening_torque(const LimitStiffening& stiffening, double positive_limit, double negative_limit,
                               double angle) {
  if (stiffening.torque == 0.0) return 0.0;
  const double s = stiffening.angle_scale;
  angle = std::clamp(angle, -negative_limit, positive_limit);
  const auto towards_limits = [&](double a) {
    return std::exp((a - positive_limit) / s) - std::exp((-negative_limit - a) / s);
  };
  return -stiffening.torque * (towards_limits(angle) - towards_limits(0.0));
}

double relaxed_wrist_torque(double stiffness, const LimitStiffening& stiffening, double positive_limit,
                            double negative_limit, double angle, double asymmetry) {
  return -stiffness * angle + stiffness_asymmetry_torque(stiffness, asymmetry, angle) +
         limit_stiffening_torque(stiffening, positive_limit, negative_limit, angle);
}

}  // namespace softwrist::physics
