#pragma once
// The ranges outside which a number in a placement file or a plugin configuration describes no fPAM or regulator,
// and the models would overflow (the plugin_config fuzzer found an 8e305 m thick wall that made the force
// infinite). Inputs outside are refused, naming the field; the ranges are wide, so no real device is.

namespace softwrist::physics::plausible {

inline constexpr double kMaxElasticModulus =
    1e12;                                      // [Pa]: five times steel's; woven fabrics are ~1e7 (the paper's 9.06e6)
inline constexpr double kMaxThickness = 0.01;  // [m]: a 1 cm fabric wall; the paper's is 0.08 mm
inline constexpr double kMaxElasticCurvature = 200.0;  // kappa: the fabric's pull grows by e every 0.5 % of strain
inline constexpr double kMaxRadius = 1.0;              // [m]: r0; the paper's is ~1.2 cm
inline constexpr double kMaxLength = 10.0;             // [m]: L0 and mount distances; the paper's L0 is ~0.3 m
inline constexpr double kMaxPressure = 1e6;            // [Pa]: 10 bar, far above a fabric muscle's burst pressure
inline constexpr double kMinTimeConstant = 1e-3;       // [s]: the regulator is integrated in MuJoCo's 1 ms steps
inline constexpr double kMaxTimeConstant = 100.0;      // [s]

}  // namespace softwrist::physics::plausible
