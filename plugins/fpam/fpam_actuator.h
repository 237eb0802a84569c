#pragma once
// The fPAM actuator plugin (softwrist.fpam): one fabric pneumatic artificial muscle on a tendon. Shaped like a
// MuJoCo 3 actuator plugin (plugin/actuator/pid.cc upstream): its configuration type with the attribute names
// (fpam_config.h), a Create that validates the configuration and returns nothing on error (with the reason), a
// static registration entry point in the adapter. The class itself knows nothing of MuJoCo's types:
// mujoco222_adapter.cc feeds it the tendon length and the regulated pressure, so moving to MuJoCo 3's plugin API
// touches only the adapter.
//
// Semantics: ctrl is the commanded pressure [kPa]; the actuator's activation is the regulated pressure [kPa], with
// first- or second-order regulator dynamics (physics/pressure_regulator.h), clamped to [0, max_pressure_kpa]. The force
// is physics::MuscleLaw's at the tendon's length: Eqn. force, with the mounts' stretch (Eqn. fabric_stretching)
// shortening the effective length; it pulls (negative along the tendon).

#include <optional>
#include <string>
#include <string_view>

#include "fpam_config.h"
#include "plugin_config.h"

namespace softwrist::plugin {

class FpamActuator {
 public:
  static constexpr std::string_view kPluginName = FpamConfig::kPluginName;

  // Validates the configuration (FpamConfig::FromConfig). On error returns nullopt and sets *error to "actuator
  // 'NAME': attribute 'KEY': problem".
  static std::optional<FpamActuator> Create(const PluginConfig& config, std::string_view actuator_name,
                                            std::string* error);

  // Regulator dynamics: d(regulated)/dt [kPa/s] towards the commanded pressure clamped to [0, max]
  // (physics/pressure_regulator.h; first order).
  double PressureRate(double commanded_kpa, double regulated_kpa) const;
  // A second-order regulator's rates of the regulated pressure [kPa/s] and of its rate [kPa/s^2] that carry an
  // explicit step of dt [s] to the exact state (physics::regulator_step): MuJoCo 2.2.2 integrates activations with
  // Euler's step, which is then exact and stable however fast the second pole. Zero rates for a non-finite input.
  struct SecondOrderRates {
    double pressure = 0.0;
    double pressure_rate = 0.0;
  };
  SecondOrderRates SecondOrderStep(double commanded_kpa, double regulated_kpa, double rate_kpa_per_s, double dt) const;
  // The fPAM's pull [N] at the tendon's length [m] and the regulated pressure [kPa] (clamped to [0, max]), on the
  // hysteresis branch `branch` (physics/fpam_hysteresis.h; ignored without hysteresis); 0 for a non-finite input (a
  // diverged simulation must not throw through MuJoCo's C code).
  double Force(double tendon_length, double regulated_kpa, double branch = 0.0) const;
  // Dahl's rate ds/dt [1/s] of the hysteresis branch at the tendon's length rate [m/s]; 0 without hysteresis or for a
  // non-finite input.
  double BranchRate(double branch, double tendon_velocity) const;

  // routing=planar (FpamConfig::PlanarPath): the muscle's torque [N m] about its own joint, in its own direction, at
  // that joint's angle in its own direction [rad]: Force at the 2D path's length times its moment arm; 0 for a
  // non-finite input.
  bool planar() const { return geometry_.has_value(); }
  double Torque(double own_angle, double regulated_kpa, double branch = 0.0) const;
  // The 2D path's length rate [m/s] at the joint's rate in the muscle's own direction [rad/s] (for BranchRate):
  // dL/dt = -moment arm x rate (virtual work).
  double PathVelocity(double own_angle, double own_rate) const;

  const FpamConfig& config() const { return config_; }

 private:
  explicit FpamActuator(FpamConfig config);
  FpamConfig config_;
  physics::StretchConstants stretch_;  // the mounts' compliance and the law's reciprocals, once (physics/muscle_law.h)
  std::optional<physics::PlacementGeometry> geometry_;  // routing=planar's path, validated once
};

}  // namespace softwrist::plugin
