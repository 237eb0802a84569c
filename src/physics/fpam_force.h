#pragma once
// The fPAM force law: Eqn. force (Naclerio & Hawkes' fPAM model: Tondu's ideal McKibben term plus a linear
// fabric-elasticity term) with the fiber angle from the maximum contraction (Eqn. fiber_orientation).
//
// Reading of the printed Eqn. force: its pressure term is printed as
//     pi P (1/sin^2(a0) - 3 (eps-1)^2 / tan^2(a0)) r0^2,
// the negative of the McKibben model it cites (Tondu 2012: F = pi r0^2 P (3 (1-eps)^2 / tan^2 a0 - 1/sin^2 a0)).
// Taken literally it pushes at eps = 0 (1 - 3 cos^2 a0 < 0 for a0 < 54.7 deg) and pushes harder as the muscle
// contracts, the opposite of the paper's tensile tests (Fig. TensileTest: force falls from its maximum at
// eps = 0 to zero at eps_max). We use Tondu's sign: an fPAM pulls, and its pull falls to zero at eps_max.
// Eqn. fiber_orientation (F = 0 at eps_max) is the same under either sign, so it is used as printed.

#include <cmath>
#include <numbers>

#include "physics/fpam_parameters.h"

namespace softwrist::physics {

// Eqn. force: eps = (L0 - L) / L0, the contraction relative to the fully stretched length L0.
double contraction_ratio(double length, double rest_length);

// Eqn. fiber_orientation: the fully stretched fiber angle alpha_0 [rad] that puts the pressure force's zero
// at eps_max: alpha_0 = -asin(sqrt(eps_max^2 - 2 eps_max + 2/3) / (eps_max - 1)), in (0, pi/2).
double fiber_angle(double max_contraction);

// Pressure-dependent term of Eqn. force (Tondu's sign, see above); negative beyond eps_max.
double pressure_force(double pressure, double contraction_ratio, const FpamCoefficients& coefficients);

// pi r0^2 P [N]: the pressure's force on the fPAM's end cap, the scale of Eqn. force's pressure term.
inline double pressure_end_force(double pressure, const FpamCoefficients& coefficients) {
  return std::numbers::pi * pressure * coefficients.radius * coefficients.radius;
}

// Pressure-independent term of Eqn. force: 2 pi E t (epsilon_0 - eps) r0 below epsilon_0, zero above it
// (Section fPAM force modeling: "We assign zero elastic force for contraction ratios larger than epsilon_0").
double fabric_elastic_force(double contraction_ratio, double radius, const FabricProperties& fabric);

// The same term with its slope 2 pi E t r0 precomputed; the one implementation both callers use. With a curvature
// kappa > 0 (FabricProperties::elastic_curvature) the J-shaped fabric: slope (exp(kappa slack) - 1) / kappa, the same
// slope at the onset, stiffer as it is stretched further.
inline double fabric_elastic_term(double contraction_ratio, double elastic_slope, double elastic_onset,
                                  double elastic_curvature = 0.0) {
  const double slack = elastic_onset - contraction_ratio;
  if (!(slack > 0.0)) return 0.0;
  return elastic_curvature > 0.0 ? elastic_slope * std::expm1(elastic_curvature * slack) / elastic_curvature
                                 : elastic_slope * slack;
}
inline double fabric_elastic_slope(double radius, const FabricProperties& fabric) {
  return 2.0 * std::numbers::pi * fabric.elastic_modulus * fabric.thickness * radius;
}

// Eqn. force at one pressure, with everything that depends only on the pressure and the fPAM worked out once
// (pi P r0^2, 3/tan^2(a0), 1/sin^2(a0), 2 pi E t r0). The free functions below evaluate through it; solvers that
// evaluate the law many times at one pressure (mount stretching, the plugin) hold one.
class FpamForceLaw {
 public:
  // Validates the inputs (InvalidParameter otherwise).
  FpamForceLaw(double pressure, const FpamCoefficients& coefficients, const FabricProperties& fabric);
  // Without the checks, for a caller that validated its fPAM's table once and clamps the pressure to >= 0: the plugin,
  // every step of every muscle, where the checks cost as much as the law (`softwrist bench sim`). Coefficients
  // interpolated between valid rows are valid.
  static FpamForceLaw Prevalidated(double pressure, const FpamCoefficients& coefficients,
                                   const FabricProperties& fabric);
  // The fPAM's pull [N] at a finite contraction ratio: both terms, never negative.
  double operator()(double contraction_ratio) const {
    const double total = pressure_term(contraction_ratio) + elastic_term(contraction_ratio);
    return total > 0.0 ? total : 0.0;
  }
  double pressure_term(double contraction_ratio) const {
    const double stretch = 1.0 - contraction_ratio;
    return mckibben_scale_ * (three_over_tan2_ * stretch * stretch - one_over_sin2_);
  }
  double elastic_term(double contraction_ratio) const {
    return fabric_elastic_term(contraction_ratio, elastic_slope_, elastic_onset_, elastic_curvature_);
  }
  // Whether the law is a quadratic in the stretch (below): a linear fabric, or where the fabric pulls nothing.
  bool elastic_is_linear() const { return elastic_curvature_ == 0.0; }
  // The law as a quadratic in the fPAM's stretch s = 1 - contraction_ratio (its length over L0), where it is positive:
  // c2 s^2 + c1 s + c0, with the fabric's elastic term (contraction below epsilon_0) or without it. For solvers that
  // use the law's form (the mounts' self-consistent stretch, muscle_law.cc); `elastic` only with a linear fabric
  // (elastic_is_linear).
  struct Quadratic {
    double c2 = 0.0, c1 = 0.0, c0 = 0.0;
  };
  Quadratic quadratic(bool elastic) const {
    if (!elastic) return {mckibben_scale_ * three_over_tan2_, 0.0, -mckibben_scale_ * one_over_sin2_};
    return {mckibben_scale_ * three_over_tan2_, elastic_slope_,
            -mckibben_scale_ * one_over_sin2_ + elastic_slope_ * (elastic_onset_ - 1.0)};
  }
  double elastic_onset() const { return elastic_onset_; }

 private:
  FpamForceLaw() = default;
  void prepare(double pressure, const FpamCoefficients& coefficients, const FabricProperties& fabric);
  double mckibben_scale_;     // pi P r0^2
  double three_over_tan2_;    // 3 / tan^2(alpha_0)
  double one_over_sin2_;      // 1 / sin^2(alpha_0)
  double elastic_slope_;      // 2 pi E t r0
  double elastic_onset_;      // epsilon_0
  double elastic_curvature_;  // kappa
};

// The fPAM's pull [N]: the sum of both terms, never negative (fabric cannot push).
double fpam_force(double pressure, double contraction_ratio, const FpamCoefficients& coefficients,
                  const FabricProperties& fabric);
double fpam_force(const FpamParameters& fpam, double pressure, double contraction_ratio);

}  // namespace softwrist::physics
