#pragma once
// Constants and unit conversions of the independent device generator. Everything inside is SI (m, Pa, N, rad, s);
// names carry the unit where it is not SI (`pressure_kpa`, `angle_deg`).

#include <cmath>
#include <numbers>

namespace softwrist::independent {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kRadPerDeg = kPi / 180.0;
inline constexpr double kPaPerKpa = 1000.0;
inline constexpr double kGravity = 9.80665;        // standard gravity [m/s^2]
inline constexpr double kRegulatorMaxKpa = 137.0;  // QB3 output range 0-137 kPa (paper, Sec. "Exosuit Prototype")

inline double to_deg(double rad) { return rad / kRadPerDeg; }
inline double to_rad(double deg) { return deg * kRadPerDeg; }

// Rounds to a grid of 1/steps_per_unit. Dividing an integer by steps_per_unit gives the double nearest to the
// decimal value (e.g. 13.7, not 13.700000000000001), so "{}" prints it short; "+ 0.0" turns -0 into 0.
inline double quantise(double value, double steps_per_unit) {
  return std::round(value * steps_per_unit) / steps_per_unit + 0.0;
}

}  // namespace softwrist::independent
