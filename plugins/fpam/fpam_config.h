#pragma once
// The configuration of one softwrist.fpam actuator: its attributes' names, read from a plugin configuration
// (FromConfig, in the style of MuJoCo's PidConfig::FromModel) and written as one (ToText, what sim/model_builder
// puts into the generated MJCF). One type, so the names and their units are stated once and a written configuration
// reads back to itself (tests/plugins/fpam_config_test.cc).

#include <array>
#include <optional>
#include <string>
#include <string_view>

#include "physics/exosuit_layout.h"
#include "physics/fpam_hysteresis.h"
#include "physics/muscle_law.h"
#include "physics/pressure_regulator.h"
#include "physics/torque_geometry.h"
#include "plugin_config.h"

namespace softwrist::plugin {

struct FpamConfig {
  static constexpr std::string_view kPluginName = "softwrist.fpam";

  // Attributes (units in the comment; SI except where the name says otherwise).
  static constexpr std::string_view kRestLength = "rest_length";                  // L0 [m], required
  static constexpr std::string_view kRadius = "r0";                               // [m] constant fPAM, with eps_max
  static constexpr std::string_view kMaxContraction = "eps_max";                  //
  static constexpr std::string_view kTablePressureKpa = "table_pressure_kpa";     // per-pressure fPAM: three lists
  static constexpr std::string_view kTableRadius = "table_r0";                    // [m]
  static constexpr std::string_view kTableMaxContraction = "table_eps_max";       //
  static constexpr std::string_view kElasticModulus = "elastic_modulus";          // E [Pa], default 9.06e6
  static constexpr std::string_view kThickness = "thickness";                     // t [m], default 0.08e-3
  static constexpr std::string_view kElasticOnset = "epsilon0";                   // default 0.153
  static constexpr std::string_view kElasticCurvature = "elastic_curvature";      // kappa, default 0 (linear fabric)
  static constexpr std::string_view kStretch = "stretch";                         // none | oneshot | selfconsistent
  static constexpr std::string_view kForearmStiffness = "K1";                     // [N/m^2], |K1| used
  static constexpr std::string_view kHandStiffness = "K2";                        // [N/m^2], |K2| used
  static constexpr std::string_view kMountExponent = "mount_exponent";            // n, default 2 (the paper's)
  static constexpr std::string_view kMountPreload = "mount_preload";              // F_p [N], default 0
  static constexpr std::string_view kMountShapedShare = "mount_shaped_share";     // s, default 1 (n, F_p alone)
  static constexpr std::string_view kMaxPressureKpa = "max_pressure_kpa";         // default 137
  static constexpr std::string_view kTimeConstant = "time_constant";              // regulator [s], default 0.1
  static constexpr std::string_view kVentTimeConstant = "vent_time_constant";     // while venting [s], default 0 (same)
  static constexpr std::string_view kSecondOrderTime = "second_order_time";       // regulator's tau2 [s], default 0
  static constexpr std::string_view kHysteresis = "hysteresis";                   // h, default 0 (none)
  static constexpr std::string_view kHysteresisLength = "hysteresis_length";      // l_h [m], default 0.002
  static constexpr std::string_view kHysteresisFriction = "hysteresis_friction";  // F_0 [N], default 0
  static constexpr std::string_view kHysteresisPressureFriction = "hysteresis_pressure_friction";  // mu, default 0
  // How the muscle's length follows the wrist (see Routing below): spatial (default) or planar, which needs the next
  // three.
  static constexpr std::string_view kRouting = "routing";
  static constexpr std::string_view kPlacement = "placement";       // d1,w1,d2,w2 [m] (torque_geometry.h)
  static constexpr std::string_view kWristRadius = "wrist_radius";  // r_w [m]
  static constexpr std::string_view kWrapSurface = "wrap_surface";  // x,y [m],aspect; default 0,0,1 (the paper's)
  static constexpr std::array<std::string_view, 28> kAttributes = {kRestLength,
                                                                   kRadius,
                                                                   kMaxContraction,
                                                                   kTablePressureKpa,
                                                                   kTableRadius,
                                                                   kTableMaxContraction,
                                                                   kElasticModulus,
                                                                   kThickness,
                                                                   kElasticOnset,
                                                                   kElasticCurvature,
                                                                   kStretch,
                                                                   kForearmStiffness,
                                                                   kHandStiffness,
                                                                   kMountExponent,
                                                                   kMountPreload,
                                                                   kMountShapedShare,
                                                                   kMaxPressureKpa,
                                                                   kTimeConstant,
                                                                   kVentTimeConstant,
                                                                   kSecondOrderTime,
                                                                   kHysteresis,
                                                                   kHysteresisLength,
                                                                   kHysteresisFriction,
                                                                   kHysteresisPressureFriction,
                                                                   kRouting,
                                                                   kPlacement,
                                                                   kWristRadius,
                                                                   kWrapSurface};

  // A muscle with hysteresis (physics/fpam_hysteresis.h) has a second state, its branch s. MuJoCo 3 would give the
  // plugin two activations; MuJoCo 2.2.2 gives an actuator one, so the state is the activation of a companion
  // actuator on the same tendon, named ACTUATOR + kHysteresisStateSuffix, configured as kHysteresisStatePlugin, with
  // no force of its own. Its activation's rate is Dahl's ds/dt from the tendon's velocity.
  static constexpr std::string_view kHysteresisStatePlugin = "softwrist.fpam.hysteresis_state";
  static constexpr std::string_view kHysteresisStateSuffix = "_hysteresis";
  // Likewise a second-order regulator (physics/pressure_regulator.h) keeps its pressure's rate in a companion named
  // ACTUATOR + kPressureRateSuffix, configured as kPressureRatePlugin.
  static constexpr std::string_view kPressureRatePlugin = "softwrist.fpam.pressure_rate";
  static constexpr std::string_view kPressureRateSuffix = "_pressure_rate";

  // spatial: the actuator is on a MuJoCo spatial tendon, whose length the plugin is given (MuJoCo routes it in 3D,
  // so a muscle also acts on the other axis and its moment arm shrinks as the wrist turns about that axis). planar:
  // the actuator is on its own joint, with gear +1 in the muscle's own direction (physics::direction_of), and the
  // plugin takes the path from the paper's 2D torque model (Eqns. tau1, tau2: physics::muscle_path) at that joint's
  // angle, so each muscle acts on its own axis alone, as the paper models it; its force is then a torque.
  struct PlanarPath {
    physics::Placement placement;
    double wrist_radius = 0.0;
    physics::WrapSurface surface;
  };
  std::optional<PlanarPath> planar;  // empty: spatial

  physics::MuscleLaw law;  // the fPAM, L0 and the mounts' stretching
  double max_pressure_kpa = physics::kRegulatorMaxPressureKpa;
  physics::RegulatorResponse regulator;  // the pressure's response to the command (sim::Regulator)
  physics::FpamHysteresis hysteresis;    // none by default: the paper's static law

  // Reads and validates a configuration. On error returns nullopt and sets *error to "actuator 'NAME': attribute
  // 'KEY': problem" (or "actuator 'NAME': problem" for one that concerns several attributes).
  static std::optional<FpamConfig> FromConfig(const PluginConfig& config, std::string_view actuator_name,
                                              std::string* error);
  // "softwrist.fpam key=value ...": every attribute that applies (K1 and K2 only when the mounts stretch, the
  // hysteresis and the regulator's second order only when not zero, so that a model without them reads as before), in
  // kAttributes' order, numbers to 10 significant digits.
  std::string ToText() const;
};

}  // namespace softwrist::plugin
