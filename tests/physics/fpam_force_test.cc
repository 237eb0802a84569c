#include "physics/fpam_force.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "physics/errors.h"
#include "physics/paper_parameters.h"

namespace softwrist::physics {
namespace {

using std::numbers::pi;

// Eqn. fiber_orientation is "derived by substituting F = 0 and eps = eps_max into Eqn. force": the fiber angle must
// make the McKibben bracket 3 (1 - eps_max)^2 / tan^2 a0 - 1 / sin^2 a0 vanish, i.e. 3 (1 - eps_max)^2 cos^2 a0 = 1.
TEST(FiberAngle, EqnFiberOrientationZeroesThePressureForceAtMaxContraction) {
  const auto fpam = paper::tensile_fpam();
  for (const auto& row : fpam.rows()) {
    const double a0 = fiber_angle(row.max_contraction);
    EXPECT_GT(a0, 0.0);
    EXPECT_LT(a0, pi / 2.0);
    const double one_minus = 1.0 - row.max_contraction;
    EXPECT_NEAR(3.0 * one_minus * one_minus * std::cos(a0) * std::cos(a0), 1.0, 1e-12) << row.max_contraction;
  }
}

// Table tensile_testing_parameters, every row: the force is zero at that row's eps_max and positive just below.
TEST(FpamForce, ZeroAtMaxContractionForEveryTensileRow) {
  const auto fpam = paper::tensile_fpam();
  for (const auto& row : fpam.rows()) {
    EXPECT_NEAR(fpam_force(fpam, row.pressure, row.max_contraction), 0.0, 1e-9) << row.pressure;
    EXPECT_GT(fpam_force(fpam, row.pressure, row.max_contraction - 0.01), 0.0) << row.pressure;
    EXPECT_EQ(fpam_force(fpam, row.pressure, row.max_contraction + 0.05), 0.0) << "never negative";
  }
}

// Eqn. force at the design values (r0 = 1.23 cm, eps_max = 0.28, 137 kPa, E = 9.06 MPa, t = 0.08 mm,
// epsilon_0 = 0.153), against an independent closed form of the same law: with cos^2 a0 = 1 / (3 (1 - eps_max)^2),
// the McKibben bracket equals ((1 - eps)^2 / (1 - eps_max)^2 - 1) / sin^2 a0.
TEST(FpamForce, EqnForceMatchesClosedFormAtDesignValues) {
  const FpamCoefficients c{.radius = 0.0123, .max_contraction = 0.28};
  const FabricProperties fabric;
  const double pressure = 137e3;
  const double sin2 = 1.0 - 1.0 / (3.0 * 0.72 * 0.72);
  for (double eps : {-0.05, 0.0, 0.1, 0.153, 0.2, 0.27}) {
    const double bracket = ((1.0 - eps) * (1.0 - eps) / (0.72 * 0.72) - 1.0) / sin2;
    const double elastic = eps < 0.153 ? 2.0 * pi * 9.06e6 * 0.08e-3 * (0.153 - eps) * 0.0123 : 0.0;
    EXPECT_NEAR(fpam_force(pressure, eps, c, fabric), pi * pressure * 0.0123 * 0.0123 * bracket + elastic, 1e-9) << eps;
  }
  // Magnitude check by hand: at eps = 0 the McKibben term is pi r0^2 P * 2.601 = 169.4 N, the fabric adds
  // 2 pi E t epsilon_0 r0 = 8.57 N.
  EXPECT_NEAR(pressure_force(pressure, 0.0, c), 169.4, 0.1);
  EXPECT_NEAR(fabric_elastic_force(0.0, 0.0123, fabric), 8.57, 0.01);
}

// FpamForceLaw evaluates Eqn. force from eps_max without trigonometry; it must equal the law written with the fiber
// angle of Eqn. fiber_orientation, as printed (with Tondu's sign).
TEST(FpamForceLaw, EqualsTheLawWrittenWithTheFiberAngle) {
  const FabricProperties fabric;
  for (const double eps_max : {0.153, 0.2, 0.277, 0.303, 0.4}) {
    const FpamCoefficients c{.radius = 0.0126, .max_contraction = eps_max};
    const double a0 = fiber_angle(eps_max);
    const FpamForceLaw law(103e3, c, fabric);
    for (double eps = -0.1; eps < 0.45; eps += 0.05) {
      const double with_angle =
          pi * 103e3 * c.radius * c.radius *
          (3.0 * (1.0 - eps) * (1.0 - eps) / std::pow(std::tan(a0), 2) - 1.0 / std::pow(std::sin(a0), 2));
      EXPECT_NEAR(law.pressure_term(eps), with_angle, 1e-9 * (1.0 + std::abs(with_angle))) << eps_max << " " << eps;
    }
  }
}

// The reading of Eqn. force's sign (fpam_force.h): the term as printed would push at eps = 0 and push harder as the
// muscle contracts; Tondu's sign pulls and weakens towards eps_max, as the tensile tests show.
TEST(FpamForce, PrintedPressureTermSignWouldPushSoWeUseTondusSign) {
  const FpamCoefficients c{.radius = 0.0123, .max_contraction = 0.28};
  const double a0 = fiber_angle(c.max_contraction);
  auto printed = [&](double eps) {
    return pi * 137e3 * (1.0 / std::pow(std::sin(a0), 2) - 3.0 * std::pow(eps - 1.0, 2) / std::pow(std::tan(a0), 2)) *
           c.radius * c.radius;
  };
  EXPECT_LT(printed(0.0), 0.0);
  EXPECT_LT(printed(0.0), printed(0.2));
  EXPECT_NEAR(pressure_force(137e3, 0.0, c), -printed(0.0), 1e-9);
  EXPECT_GT(pressure_force(137e3, 0.0, c), pressure_force(137e3, 0.2, c));
}

// Section fPAM force modeling: "We assign zero elastic force for contraction ratios larger than epsilon_0".
TEST(FpamForce, ElasticTermVanishesAboveEpsilonZeroSoDeflatedMuscleIsSlack) {
  const FabricProperties fabric;
  EXPECT_EQ(fabric_elastic_force(0.153, 0.0123, fabric), 0.0);
  EXPECT_EQ(fabric_elastic_force(0.2, 0.0123, fabric), 0.0);
  EXPECT_GT(fabric_elastic_force(0.15, 0.0123, fabric), 0.0);
  const auto fpam = paper::tensile_fpam();
  EXPECT_EQ(fpam_force(fpam, 0.0, 0.16), 0.0);
  EXPECT_NEAR(fpam_force(fpam, 0.0, 0.0), fabric_elastic_force(0.0, 0.0123, fabric), 1e-12);
}

// The J-shaped fabric (FabricProperties::elastic_curvature, the paper's exponential fit of its 0 kPa tensile curve):
// the same slope 2 pi E t r0 at the onset eps_0, stiffer as it is stretched further, slack above eps_0; the linear
// term in the limit kappa -> 0, and a curvature outside [0, 200] refused by name.
TEST(FpamForce, CurvedFabricKeepsItsOnsetSlopeAndStiffensTowardsFullStretch) {
  const FabricProperties linear;
  const FabricProperties curved{.elastic_curvature = 20.0};
  const double r0 = 0.0123, slope = fabric_elastic_slope(r0, linear), eps0 = linear.elastic_onset_contraction;
  EXPECT_EQ(fabric_elastic_force(0.16, r0, curved), 0.0);
  EXPECT_NEAR(fabric_elastic_force(0.0, r0, curved), slope * std::expm1(20.0 * eps0) / 20.0, 1e-12);
  EXPECT_NEAR((fabric_elastic_force(eps0 - 1e-6, r0, curved)) / 1e-6, slope, 1e-4 * slope);  // the onset's slope
  EXPECT_GT(fabric_elastic_force(0.0, r0, curved), 5.0 * fabric_elastic_force(0.0, r0, linear));
  const FabricProperties nearly{.elastic_curvature = 1e-9};
  for (const double eps : {0.0, 0.05, 0.15})
    EXPECT_NEAR(fabric_elastic_force(eps, r0, nearly), fabric_elastic_force(eps, r0, linear), 1e-9);
  const auto fpam = FpamParameters::Constant(r0, 0.28, curved);
  EXPECT_NEAR(fpam_force(fpam, 0.0, 0.02), fabric_elastic_force(0.02, r0, curved), 1e-12);
  for (const double bad : {-1.0, 250.0, std::nan("")}) {
    try {
      validate(FabricProperties{.elastic_curvature = bad});
      ADD_FAILURE() << bad;
    } catch (const InvalidParameter& e) {
      EXPECT_NE(std::string(e.what()).find("elastic_curvature"), std::string::npos) << e.what();
    }
  }
}

TEST(FpamForce, FallsMonotonicallyAsTheMuscleContracts) {
  const auto fpam = paper::tensile_fpam();
  for (double pressure : {34e3, 68e3, 103e3, 137e3}) {
    double previous = fpam_force(fpam, pressure, -0.05);
    for (double eps = -0.04; eps < 0.35; eps += 0.01) {
      const double force = fpam_force(fpam, pressure, eps);
      EXPECT_LE(force, previous) << pressure << " " << eps;
      previous = force;
    }
  }
}

TEST(ContractionRatio, IsRelativeShorteningFromRestLength) {
  EXPECT_DOUBLE_EQ(contraction_ratio(0.30, 0.34), (0.34 - 0.30) / 0.34);
  EXPECT_DOUBLE_EQ(contraction_ratio(0.34, 0.34), 0.0);
  EXPECT_THROW(contraction_ratio(0.3, 0.0), InvalidParameter);
  EXPECT_THROW(contraction_ratio(0.3, -0.34), InvalidParameter);
  EXPECT_THROW(contraction_ratio(std::nan(""), 0.34), InvalidParameter);
}

TEST(FpamForce, RejectsNegativeOrNanPressureAndNanContraction) {
  const auto fpam = paper::design_fpam();
  EXPECT_THROW(fpam_force(fpam, -1.0, 0.1), InvalidParameter);
  EXPECT_THROW(fpam_force(fpam, std::nan(""), 0.1), InvalidParameter);
  EXPECT_THROW(fpam_force(fpam, 100e3, std::nan("")), InvalidParameter);
  EXPECT_THROW(fiber_angle(0.5), InvalidParameter);
}

}  // namespace
}  // namespace softwrist::physics
