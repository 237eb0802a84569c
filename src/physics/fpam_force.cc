#include "physics/fpam_force.h"

#include <cmath>
#include <numbers>

#include "physics/errors.h"

namespace softwrist::physics {

double contraction_ratio(double length, double rest_length) {
  require_positive("rest_length L0 [m]", rest_length);
  require_non_negative("muscle length L [m]", length);
  return (rest_length - length) / rest_length;
}

double fiber_angle(double max_contraction) {
  validate(FpamCoefficients{.radius = 1.0, .max_contraction = max_contraction});  // checks eps_max only
  const double eps = max_contraction;
  return -std::asin(std::sqrt(eps * eps - 2.0 * eps + 2.0 / 3.0) / (eps - 1.0));
}

FpamForceLaw::FpamForceLaw(double pressure, const FpamCoefficients& coefficients, const FabricProperties& fabric) {
  require_non_negative("pressure [Pa]", pressure);
  validate(coefficients);
  prepare(pressure, coefficients, fabric);
}

FpamForceLaw FpamForceLaw::Prevalidated(double pressure, const FpamCoefficients& coefficients,
                                        const FabricProperties& fabric) {
  FpamForceLaw law;
  law.prepare(pressure, coefficients, fabric);
  return law;
}

void FpamForceLaw::prepare(double pressure, const FpamCoefficients& coefficients, const FabricProperties& fabric) {
  // Eqn. fiber_orientation substituted without trigonometry: it is cos^2(alpha_0) = 1 / t with t = 3 (1 - eps_max)^2,
  // so sin^2 = (t - 1) / t, 1 / sin^2 = t / (t - 1) and 3 / tan^2 = 3 cos^2 / sin^2 = 3 / (t - 1): one division, the
  // plugin preparing the law every step (fpam_force_test.cc checks this against fiber_angle()).
  const double one_minus = 1.0 - coefficients.max_contraction;
  const double t = 3.0 * one_minus * one_minus;
  const double inverse = 1.0 / (t - 1.0);
  const double r0 = coefficients.radius;
  mckibben_scale_ = pressure_end_force(pressure, coefficients);
  three_over_tan2_ = 3.0 * inverse;
  one_over_sin2_ = t * inverse;
  elastic_slope_ = fabric_elastic_slope(r0, fabric);
  elastic_onset_ = fabric.elastic_onset_contraction;
  elastic_curvature_ = fabric.elastic_curvature;
}

double pressure_force(double pressure, double contraction_ratio, const FpamCoefficients& coefficients) {
  require_finite("contraction_ratio", contraction_ratio);
  return FpamForceLaw(pressure, coefficients, FabricProperties{}).pressure_term(contraction_ratio);
}

double fabric_elastic_force(double contraction_ratio, double radius, const FabricProperties& fabric) {
  require_finite("contraction_ratio", contraction_ratio);
  return fabric_elastic_term(contraction_ratio, fabric_elastic_slope(radius, fabric), fabric.elastic_onset_contraction,
                             fabric.elastic_curvature);
}

double fpam_force(double pressure, double contraction_ratio, const FpamCoefficients& coefficients,
                  const FabricProperties& fabric) {
  require_finite("contraction_ratio", contraction_ratio);
  return FpamForceLaw(pressure, coefficients, fabric)(contraction_ratio);
}

double fpam_force(const FpamParameters& fpam, double pressure, double contraction_ratio) {
  return fpam_force(pressure, contraction_ratio, fpam.at_pressure(pressure), fpam.fabric());
}

}  // namespace softwrist::physics
