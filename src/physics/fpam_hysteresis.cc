#include "physics/fpam_hysteresis.h"

#include <algorithm>
#include <cmath>

#include "physics/errors.h"

namespace softwrist::physics {

double hysteresis_state_rate(const FpamHysteresis& hysteresis, double state, double length_rate) {
  return (length_rate - std::abs(length_rate) * state) / hysteresis.transition_length;
}

double hysteretic_force(const FpamHysteresis& hysteresis, double static_force, double state,
                        double pressure_end_force) {
  const double friction =
      std::min(static_force, hysteresis.friction_force + hysteresis.pressure_friction * pressure_end_force);
  const double force = static_force + std::clamp(state, -1.0, 1.0) * (hysteresis.fraction * static_force + friction);
  return force > 0.0 ? force : 0.0;
}

double hysteresis_state_after(const FpamHysteresis& hysteresis, double state, double lengthening) {
  if (lengthening == 0.0) return state;
  const double sign = lengthening > 0.0 ? 1.0 : -1.0;
  return sign + (state - sign) * std::exp(-std::abs(lengthening) / hysteresis.transition_length);
}

void validate(const FpamHysteresis& hysteresis) {
  require(std::isfinite(hysteresis.fraction) && hysteresis.fraction >= 0.0 && hysteresis.fraction < 0.5, "hysteresis",
          hysteresis.fraction, "must be >= 0 and < 0.5");
  require(std::isfinite(hysteresis.friction_force) && hysteresis.friction_force >= 0.0, "hysteresis_friction",
          hysteresis.friction_force, "must be >= 0 (N)");
  require(std::isfinite(hysteresis.pressure_friction) && hysteresis.pressure_friction >= 0.0 &&
              hysteresis.pressure_friction < 1.0,
          "hysteresis_pressure_friction", hysteresis.pressure_friction, "must be >= 0 and < 1");
  require_positive("hysteresis_length", hysteresis.transition_length);
}

}  // namespace softwrist::physics
