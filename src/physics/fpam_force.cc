#include "physics/fpam_force.h"

#include <algorithm>
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

double pressure_force(double pressure, double contraction_ratio, const FpamCoefficients& coefficients) {
  require_non_negative("pressure [Pa]", pressure);
  require_finite("contraction_ratio", contraction_ratio);
  validate(coefficients);
  const double alpha0 = fiber_angle(coefficients.max_contraction);
  const double sin_a = std::sin(alpha0);
  const double tan_a = std::tan(alpha0);
  const double stretch = 1.0 - contraction_ratio;
  const double r0 = coefficients.radius;
  return std::numbers::pi * pressure * r0 * r0 *
         (3.0 * stretch * stretch / (tan_a * tan_a) - 1.0 / (sin_a * sin_a));
}

double fabric_elastic_force(double contraction_ratio, double radius, const FabricProperties& fabric) {
  require_finite("contraction_ratio", contraction_ratio);
  const double slack = fabric.elastic_onset_contraction - contraction_ratio;
  if (slack <= 0.0) return 0.0;
  return 2.0 * std::numbers::pi * fabric.elastic_modulus * fabric.thickness * slack * radius;
}

double fpam_force(double pressure, double contraction_ratio, const FpamCoefficients& coefficients,
                  const FabricProperties& fabric) {
  const double total = pressure_force(pressure, contraction_ratio, coefficients) +
                       fabric_elastic_force(contraction_ratio, coefficients.radius, fabric);
  return std::max(0.0, total);
}

double fpam_force(const FpamParameters& fpam, double pressure, double contraction_ratio) {
  return fpam_force(pressure, contraction_ratio, fpam.at_pressure(pressure), fpam.fabric());
}

}  // namespace softwrist::physics
