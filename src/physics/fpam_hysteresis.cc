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

std::optional<HysteresisProblem> hysteresis_problem(const FpamHysteresis& h) {
  using F = HysteresisField;
  if (!(std::isfinite(h.fraction) && h.fraction >= 0.0 && h.fraction < 0.5))
    return HysteresisProblem{F::kFraction, h.fraction, "must be >= 0 and < 0.5"};
  if (!(std::isfinite(h.friction_force) && h.friction_force >= 0.0))
    return HysteresisProblem{F::kFrictionForce, h.friction_force, "must be >= 0 (N)"};
  if (!(std::isfinite(h.pressure_friction) && h.pressure_friction >= 0.0 && h.pressure_friction < 1.0))
    return HysteresisProblem{F::kPressureFriction, h.pressure_friction, "must be >= 0 and < 1"};
  if (!(std::isfinite(h.transition_length) && h.transition_length > 0.0))
    return HysteresisProblem{F::kTransitionLength, h.transition_length, "must be a finite number > 0"};
  return std::nullopt;
}

void validate(const FpamHysteresis& hysteresis) {
  static constexpr const char* kNames[] = {"hysteresis", "hysteresis_friction", "hysteresis_pressure_friction",
                                           "hysteresis_length"};
  if (const auto p = hysteresis_problem(hysteresis))
    require(false, kNames[static_cast<int>(p->field)], p->value, p->requirement);
}

}  // namespace softwrist::physics
