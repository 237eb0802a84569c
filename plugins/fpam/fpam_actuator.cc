#include "fpam_actuator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "physics/fpam_force.h"
#include "physics/fpam_hysteresis.h"
#include "physics/mount_stretch.h"
#include "physics/pressure_regulator.h"
#include "physics/units.h"

namespace softwrist::plugin {

std::optional<FpamActuator> FpamActuator::Create(const PluginConfig& config, std::string_view actuator_name,
                                                 std::string* error) {
  auto read = FpamConfig::FromConfig(config, actuator_name, error);
  if (!read) return std::nullopt;
  return FpamActuator(std::move(*read));
}

FpamActuator::FpamActuator(FpamConfig config)
    : config_(std::move(config)), stretch_(physics::stretch_constants(config_.law)) {
  // FromConfig validated the path, so the constructor cannot throw here.
  if (const auto& path = config_.planar) geometry_.emplace(path->placement, path->wrist_radius, path->surface);
}

double FpamActuator::PressureRate(double commanded_kpa, double regulated_kpa) const {
  if (!std::isfinite(commanded_kpa) || !std::isfinite(regulated_kpa)) return 0.0;
  return physics::pressure_rate(config_.regulator, std::clamp(commanded_kpa, 0.0, config_.max_pressure_kpa),
                                regulated_kpa);
}

FpamActuator::SecondOrderRates FpamActuator::SecondOrderStep(double commanded_kpa, double regulated_kpa,
                                                             double rate_kpa_per_s, double dt) const {
  if (!std::isfinite(commanded_kpa) || !std::isfinite(regulated_kpa) || !std::isfinite(rate_kpa_per_s) || !(dt > 0.0))
    return {};
  const physics::RegulatedPressure after = physics::regulator_step(
      config_.regulator, {regulated_kpa, rate_kpa_per_s}, std::clamp(commanded_kpa, 0.0, config_.max_pressure_kpa), dt);
  return {(after.pressure - regulated_kpa) / dt, (after.rate - rate_kpa_per_s) / dt};
}

double FpamActuator::Force(double tendon_length, double regulated_kpa, double branch) const {
  if (!std::isfinite(tendon_length) || !std::isfinite(regulated_kpa) || tendon_length < 0.0) return 0.0;
  const physics::MuscleLaw& law = config_.law;
  const double pressure = units::kpa_to_pa(std::clamp(regulated_kpa, 0.0, config_.max_pressure_kpa));
  const physics::FpamCoefficients coefficients = law.fpam.at_pressure(pressure);
  // The table was validated in FromConfig and the pressure is clamped to >= 0 above.
  const auto force_law = physics::FpamForceLaw::Prevalidated(pressure, coefficients, law.fpam.fabric());
  const double force = physics::stretched_force(law, force_law, tendon_length, stretch_).force;
  if (!config_.hysteresis.active() || !std::isfinite(branch)) return force;
  return physics::hysteretic_force(config_.hysteresis, force, branch,
                                   physics::pressure_end_force(pressure, coefficients));
}

namespace {

// The path at a joint angle clamped to [-pi, pi], where the 2D geometry is defined (it throws beyond, and nothing may
// throw through MuJoCo's C code: a diverging simulation is caught by its instability check instead).
physics::MusclePath PathAt(const physics::PlacementGeometry& geometry, double own_angle) {
  return geometry.at(std::clamp(own_angle, -std::numbers::pi, std::numbers::pi));
}

}  // namespace

double FpamActuator::Torque(double own_angle, double regulated_kpa, double branch) const {
  if (!geometry_ || !std::isfinite(own_angle)) return 0.0;
  const physics::MusclePath path = PathAt(*geometry_, own_angle);
  return Force(path.length, regulated_kpa, branch) * path.moment_arm;
}

double FpamActuator::PathVelocity(double own_angle, double own_rate) const {
  if (!geometry_ || !std::isfinite(own_angle) || !std::isfinite(own_rate)) return 0.0;
  return -PathAt(*geometry_, own_angle).moment_arm * own_rate;
}

double FpamActuator::BranchRate(double branch, double tendon_velocity) const {
  if (!config_.hysteresis.active() || !std::isfinite(branch) || !std::isfinite(tendon_velocity)) return 0.0;
  return physics::hysteresis_state_rate(config_.hysteresis, branch, tendon_velocity);
}

}  // namespace softwrist::plugin
