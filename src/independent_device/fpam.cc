#include "independent_device/fpam.h"

#include <algorithm>
#include <cmath>

#include "independent_device/units.h"

namespace softwrist::independent {
namespace {

double interpolate(const std::array<double, 5>& xs, const std::array<double, 5>& ys, double x) {
  if (x <= xs.front()) return ys.front();
  for (std::size_t i = 1; i < xs.size(); ++i) {
    if (x <= xs[i]) {
      const double f = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
      return ys[i - 1] + f * (ys[i] - ys[i - 1]);
    }
  }
  return ys.back();
}

}  // namespace

double max_contraction(const FpamLaw& law, double pressure_kpa) {
  double e = interpolate(law.table_pressure_kpa, law.table_max_contraction, pressure_kpa) + law.max_contraction_offset;
  e -= law.aged_contraction_drop_at_max * std::clamp(pressure_kpa / kRegulatorMaxKpa, 0.0, 1.0);
  // Below 1 - 1/sqrt(3) = 0.42 so that a fibre angle exists (the McKibben limit of 54.7 deg).
  return std::clamp(e, 0.02, 0.40);
}

double fpam_radius_m(const FpamLaw& law, double pressure_kpa) {
  return interpolate(law.table_pressure_kpa, law.table_radius_m, pressure_kpa) * law.radius_scale *
         (1.0 + law.aged_radius_gain);
}

FpamAtPressure fpam_at_pressure(const FpamLaw& law, double pressure_pa) {
  FpamAtPressure at;
  const double pressure_kpa = pressure_pa / kPaPerKpa;
  at.pressure_pa = std::max(0.0, pressure_pa);
  at.radius_m = fpam_radius_m(law, pressure_kpa);
  // Fibre angle from F = 0 at e_max (paper Eq. fiber_orientation): cos^2 a0 = 1 / (3 (1 - e_max)^2).
  at.max_contraction = max_contraction(law, pressure_kpa);
  const double cos2 = 1.0 / (3.0 * (1.0 - at.max_contraction) * (1.0 - at.max_contraction));
  const double sin2 = 1.0 - cos2;
  at.a = 3.0 * cos2 / sin2;
  at.b = 1.0 / sin2;
  at.area_force_n = kPi * at.radius_m * at.radius_m * at.pressure_pa;
  if (law.exponential_force_at_full_stretch_n > 0.0) {
    const double x0 = law.slack_contraction / law.exponential_strain_scale;
    at.exponential_amplitude_n = law.exponential_force_at_full_stretch_n / (std::exp(x0) - 1.0 - x0);
  }
  return at;
}

double fpam_force_n(const FpamLaw& law, const FpamAtPressure& at, double contraction) {
  double force = 0.0;
  if (at.pressure_pa > 0.0) {
    const double u = 1.0 - law.tondu_end_factor * contraction;
    if (u > 1.0 - at.max_contraction) force += at.area_force_n * (at.a * u * u - at.b);
  }
  const double x = law.slack_contraction - contraction;  // how far below e0 the fabric is stretched
  if (x > 0.0) {
    force += 2.0 * kPi * law.modulus_pa * law.thickness_m * x * at.radius_m;  // paper Eq. (force), second term
    if (at.exponential_amplitude_n > 0.0) {
      const double xs = x / law.exponential_strain_scale;
      force += at.exponential_amplitude_n * (std::exp(xs) - 1.0 - xs);
    }
  }
  return std::max(0.0, force);
}

double fpam_force_n(const FpamLaw& law, double contraction, double pressure_pa) {
  return fpam_force_n(law, fpam_at_pressure(law, pressure_pa), contraction);
}

}  // namespace softwrist::independent
