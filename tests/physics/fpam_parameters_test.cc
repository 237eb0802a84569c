#include "physics/fpam_parameters.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "physics/errors.h"
#include "physics/paper_parameters.h"

namespace softwrist::physics {
namespace {

// Table tensile_testing_parameters: the rows come back exactly at their pressures.
TEST(FpamParameters, TensileTableRowsAtTheirPressures) {
  const auto fpam = paper::tensile_fpam();
  const double radius_cm[] = {1.23, 1.27, 1.22, 1.19, 1.26};
  const double eps_max[] = {0.153, 0.303, 0.296, 0.301, 0.277};
  for (std::size_t i = 0; i < paper::kMeasurementPressures.size(); ++i) {
    const auto c = fpam.at_pressure(paper::kMeasurementPressures[i]);
    EXPECT_DOUBLE_EQ(c.radius, radius_cm[i] / 100.0) << "row " << i;
    EXPECT_DOUBLE_EQ(c.max_contraction, eps_max[i]) << "row " << i;
  }
}

TEST(FpamParameters, InterpolatesLinearlyBetweenRowsAndHoldsOutside) {
  const auto fpam = paper::tensile_fpam();
  const auto mid = fpam.at_pressure(51e3);  // halfway between the 34 and 68 kPa rows
  EXPECT_NEAR(mid.radius, 0.5 * (0.0127 + 0.0122), 1e-15);
  EXPECT_NEAR(mid.max_contraction, 0.5 * (0.303 + 0.296), 1e-15);
  const auto above = fpam.at_pressure(312e3);
  EXPECT_DOUBLE_EQ(above.max_contraction, 0.277);
}

TEST(FpamParameters, ConstantIsTheSameAtEveryPressure) {
  const auto fpam = paper::design_fpam();
  EXPECT_TRUE(fpam.is_constant());
  for (double p : {0.0, 50e3, 137e3, 312e3}) {
    EXPECT_DOUBLE_EQ(fpam.at_pressure(p).radius, 0.0123);
    EXPECT_DOUBLE_EQ(fpam.at_pressure(p).max_contraction, 0.28);
  }
}

TEST(FpamParameters, RejectsInvalidParametersNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double eps : {0.0, -0.1, 1.0, 1.5, nan}) {
    try {
      FpamParameters::Constant(0.01, eps);
      FAIL() << "accepted eps_max " << eps;
    } catch (const InvalidParameter& e) {
      EXPECT_NE(std::string(e.what()).find("max_contraction eps_max"), std::string::npos) << e.what();
    }
  }
  // Eqn. fiber_orientation has no real fiber angle above 1 - 1/sqrt(3).
  EXPECT_THROW(FpamParameters::Constant(0.01, 0.43), InvalidParameter);
  EXPECT_NO_THROW(FpamParameters::Constant(0.01, 0.42));
  EXPECT_THROW(FpamParameters::Constant(-0.01, 0.28), InvalidParameter);
  EXPECT_THROW(FpamParameters::Constant(nan, 0.28), InvalidParameter);
  EXPECT_THROW(FpamParameters::Table({}), InvalidParameter);
  EXPECT_THROW(FpamParameters::Table({{10e3, 0.01, 0.2}, {10e3, 0.01, 0.2}}), InvalidParameter);
  EXPECT_THROW(FpamParameters::Table({{-1.0, 0.01, 0.2}}), InvalidParameter);
  EXPECT_THROW(FpamParameters::Constant(0.01, 0.28, FabricProperties{.elastic_modulus = -1.0}), InvalidParameter);
  EXPECT_THROW(FpamParameters::Constant(0.01, 0.28, FabricProperties{.elastic_onset_contraction = 1.0}),
               InvalidParameter);
  EXPECT_THROW(paper::design_fpam().at_pressure(-1.0), InvalidParameter);
  EXPECT_THROW(paper::design_fpam().at_pressure(nan), InvalidParameter);
}

}  // namespace
}  // namespace softwrist::physics

namespace softwrist::physics {
namespace {

// The one way to edit an fPAM: same fabric, the edited rows validated like a new table.
TEST(FpamParameters, WithRowsKeepsTheFabricAndValidatesTheRows) {
  const FabricProperties fabric{.elastic_modulus = 8e6, .thickness = 0.1e-3, .elastic_onset_contraction = 0.15};
  const FpamParameters table = FpamParameters::Table({{0.0, 0.012, 0.15}, {137e3, 0.0126, 0.277}}, fabric);
  auto rows = table.rows();
  rows[1].radius = 0.013;
  const FpamParameters edited = table.with_rows(rows);
  EXPECT_DOUBLE_EQ(edited.at_pressure(137e3).radius, 0.013);
  EXPECT_DOUBLE_EQ(edited.fabric().elastic_modulus, 8e6);
  EXPECT_TRUE(table.with_rows({rows[1]}).is_constant());
  rows[1].pressure = 0.0;  // not increasing
  EXPECT_THROW(table.with_rows(rows), InvalidParameter);
  EXPECT_THROW(table.with_rows({}), InvalidParameter);
}

// One fPAM's departure from another's table (a muscle cut and sealed on its own, sim::MuscleMount): every row's r0
// scaled and eps_max shifted, the fabric kept, the result validated as a table is.
TEST(FpamParameters, ScaledScalesEveryRowsRadiusAndShiftsItsMaxContraction) {
  const FabricProperties fabric{.elastic_modulus = 8e6, .thickness = 0.1e-3, .elastic_onset_contraction = 0.15};
  const FpamParameters table = FpamParameters::Table({{0.0, 0.012, 0.15}, {137e3, 0.0126, 0.277}}, fabric);
  const FpamParameters own = table.scaled(1.02, -0.005);
  EXPECT_DOUBLE_EQ(own.at_pressure(0.0).radius, 1.02 * 0.012);
  EXPECT_DOUBLE_EQ(own.at_pressure(137e3).max_contraction, 0.272);
  EXPECT_DOUBLE_EQ(own.at_pressure(137e3).radius, 1.02 * 0.0126);
  EXPECT_EQ(own.fabric(), table.fabric());
  EXPECT_THROW((void)table.scaled(-1.0, 0.0), InvalidParameter);
  EXPECT_THROW((void)table.scaled(1.0, 0.3), InvalidParameter);  // eps_max beyond Eqn. fiber_orientation's bound
}

}  // namespace
}  // namespace softwrist::physics
