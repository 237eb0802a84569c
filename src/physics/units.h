#pragma once
// Unit conversions for the edges of softwrist (command line, config files, tables). Everything inside the
// code is SI: metres, pascals, newtons, radians; a value in another unit carries it in its name.

#include <numbers>

namespace softwrist::units {

inline constexpr double kpa_to_pa(double pressure_kpa) { return pressure_kpa * 1e3; }
inline constexpr double pa_to_kpa(double pressure) { return pressure * 1e-3; }
inline constexpr double cm_to_m(double length_cm) { return length_cm * 1e-2; }
inline constexpr double m_to_cm(double length) { return length * 1e2; }
inline constexpr double mm_to_m(double length_mm) { return length_mm * 1e-3; }
inline constexpr double m_to_mm(double length) { return length * 1e3; }
inline constexpr double deg_to_rad(double angle_deg) { return angle_deg * std::numbers::pi / 180.0; }
inline constexpr double rad_to_deg(double angle) { return angle * 180.0 / std::numbers::pi; }
// Mounting stiffness K of Eqn. fabric_stretching: the paper states it in N/cm^2.
inline constexpr double n_per_cm2_to_n_per_m2(double stiffness_n_per_cm2) { return stiffness_n_per_cm2 * 1e4; }
inline constexpr double n_per_m2_to_n_per_cm2(double stiffness) { return stiffness * 1e-4; }

}  // namespace softwrist::units
