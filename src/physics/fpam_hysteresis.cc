#include "physics/fpam_hysteresis.h"

#include <algorithm>
#include <cmath>

#include "physics/errors.h"

namespace softwrist::physics {

double hysteresis_state_rate(const FpamHysteresis& hysteresis, double state, double length_rate) {
  return (length_rate - std::abs(length_rate) * state) / hysteresis.transition_length;
}

double hysteretic_force(const FpamHysteresis& hysteresis, double static_force, double state) {
  return static_force * (1.0 + hysteresis.fraction * std::clamp(state, -1.0, 1.0));
}

void validate(const FpamHysteresis& hysteresis) {
  require(std::isfinite(hysteresis.fraction) && hysteresis.fraction >= 0.0 && hysteresis.fraction < 0.5, "hysteresis",
          hysteresis.fraction, "must be >= 0 and < 0.5");
  require_positive("hysteresis_length", hysteresis.transition_length);
}

}  // namespace softwrist::physics
