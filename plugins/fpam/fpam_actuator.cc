#include "fpam_actuator.h"

#include <algorithm>
#include <cmath>

#include "physics/fpam_force.h"
#include "physics/fpam_hysteresis.h"
#include "physics/mount_stretch.h"
#include "physics/units.h"

namespace softwrist::plugin {

std::optional<FpamActuator> FpamActuator::Create(const PluginConfig& config, std::string_view actuator_name,
                                                 std::string* error) {
  auto read = FpamConfig::FromConfig(config, actuator_name, error);
  if (!read) return std::nullopt;
  return FpamActuator(std::move(*read));
}

FpamActuator::FpamActuator(FpamConfig config)
    : config_(std::move(config)), mount_compliance_(physics::mount_compliance(config_.law.mount_stiffness)) {}

double FpamActuator::PressureRate(double commanded_kpa, double regulated_kpa) const {
  if (!std::isfinite(commanded_kpa) || !std::isfinite(regulated_kpa)) return 0.0;
  const double error_kpa = std::clamp(commanded_kpa, 0.0, config_.max_pressure_kpa) - regulated_kpa;
  // First order, with the venting time constant while the pressure falls where it has one (sim::Regulator).
  const double tau =
      error_kpa < 0.0 && config_.vent_time_constant > 0.0 ? config_.vent_time_constant : config_.time_constant;
  return error_kpa / tau;
}

double FpamActuator::Force(double tendon_length, double regulated_kpa, double branch) const {
  if (!std::isfinite(tendon_length) || !std::isfinite(regulated_kpa) || tendon_length < 0.0) return 0.0;
  const physics::MuscleLaw& law = config_.law;
  const double pressure = units::kpa_to_pa(std::clamp(regulated_kpa, 0.0, config_.max_pressure_kpa));
  const physics::FpamCoefficients coefficients = law.fpam.at_pressure(pressure);
  // The table was validated in FromConfig and the pressure is clamped to >= 0 above.
  const auto force_law = physics::FpamForceLaw::Prevalidated(pressure, coefficients, law.fpam.fabric());
  const double force = physics::stretched_force(law, force_law, tendon_length, mount_compliance_).force;
  if (!config_.hysteresis.active() || !std::isfinite(branch)) return force;
  return physics::hysteretic_force(config_.hysteresis, force, branch,
                                   physics::pressure_end_force(pressure, coefficients));
}

double FpamActuator::BranchRate(double branch, double tendon_velocity) const {
  if (!config_.hysteresis.active() || !std::isfinite(branch) || !std::isfinite(tendon_velocity)) return 0.0;
  return physics::hysteresis_state_rate(config_.hysteresis, branch, tendon_velocity);
}

}  // namespace softwrist::plugin
