#pragma once
// The fPAM actuator plugin (softwrist.fpam): one fabric pneumatic artificial muscle on a tendon. Shaped like a
// MuJoCo 3 actuator plugin (plugin/actuator/pid.cc upstream): attribute names as constants, a Create that validates
// the configuration and returns nothing on error (with the reason), a static registration entry point in the
// adapter. The class itself knows nothing of MuJoCo's types: mujoco222_adapter.cc feeds it the tendon length and
// the regulated pressure, so moving to MuJoCo 3's plugin API touches only the adapter.
//
// Semantics: ctrl is the commanded pressure [kPa]; the actuator's activation is the regulated pressure [kPa], with
// first-order regulator dynamics, clamped to [0, max_pressure_kpa]. The force is Eqn. force at the tendon's length,
// with the mounts' stretch (Eqn. fabric_stretching) shortening the effective length; it pulls (negative along the
// tendon). All laws come from src/physics.

#include <array>
#include <optional>
#include <string>
#include <string_view>

#include "physics/fpam_parameters.h"
#include "physics/mount_stretch.h"
#include "plugin_config.h"

namespace softwrist::plugin {

class FpamActuator {
 public:
  static constexpr std::string_view kPluginName = "softwrist.fpam";

  // Attributes (units in the comment; SI except where the name says otherwise).
  static constexpr std::string_view kRestLength = "rest_length";              // L0 [m], required
  static constexpr std::string_view kRadius = "r0";                           // [m] constant fPAM, with eps_max
  static constexpr std::string_view kMaxContraction = "eps_max";              //
  static constexpr std::string_view kTablePressureKpa = "table_pressure_kpa"; // per-pressure fPAM: three lists
  static constexpr std::string_view kTableRadius = "table_r0";                // [m]
  static constexpr std::string_view kTableMaxContraction = "table_eps_max";   //
  static constexpr std::string_view kElasticModulus = "elastic_modulus";      // E [Pa], default 9.06e6
  static constexpr std::string_view kThickness = "thickness";                 // t [m], default 0.08e-3
  static constexpr std::string_view kElasticOnset = "epsilon0";               // default 0.153
  static constexpr std::string_view kStretch = "stretch";                     // none | oneshot | selfconsistent
  static constexpr std::string_view kForearmStiffness = "K1";                 // [N/m^2], |K1| used
  static constexpr std::string_view kHandStiffness = "K2";                    // [N/m^2], |K2| used
  static constexpr std::string_view kMaxPressureKpa = "max_pressure_kpa";     // default 137
  static constexpr std::string_view kTimeConstant = "time_constant";          // regulator [s], default 0.1
  static constexpr std::array<std::string_view, 14> kAttributes = {
      kRestLength,   kRadius,    kMaxContraction,   kTablePressureKpa, kTableRadius,    kTableMaxContraction,
      kElasticModulus, kThickness, kElasticOnset, kStretch,          kForearmStiffness, kHandStiffness,
      kMaxPressureKpa, kTimeConstant};

  // Validates the configuration. On error returns nullopt and sets *error to "actuator 'NAME': attribute 'KEY':
  // problem".
  static std::optional<FpamActuator> Create(const PluginConfig& config, std::string_view actuator_name,
                                            std::string* error);

  // Regulator dynamics: d(regulated)/dt [kPa/s] towards the commanded pressure clamped to [0, max].
  double PressureRate(double commanded_kpa, double regulated_kpa) const;
  // The fPAM's pull [N] at the tendon's length [m] and the regulated pressure [kPa] (clamped to [0, max]); 0 for a
  // non-finite input (a diverged simulation must not throw through MuJoCo's C code).
  double Force(double tendon_length, double regulated_kpa) const;


 private:
  FpamActuator(physics::FpamParameters fpam) : fpam_(std::move(fpam)) {}
  physics::FpamParameters fpam_;
  double rest_length_ = 0.0;
  physics::StretchMode stretch_mode_ = physics::StretchMode::kNone;
  physics::MountStiffness mount_stiffness_;
  double max_pressure_kpa_ = 137.0;
  double time_constant_ = 0.1;
};

}  // namespace softwrist::plugin
