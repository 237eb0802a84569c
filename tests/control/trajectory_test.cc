// The desired trajectories of Section Control and Demonstration.

#include "control/trajectory.h"

#include <cmath>

#include <gtest/gtest.h>

namespace softwrist::control {
namespace {

// Section Planar angle tracking: each level holds for hold_s, the last one to the end; rates are zero.
TEST(StepTrajectory, HoldsEachLevelForItsTime) {
  const StepTrajectory steps({{0.0, 0.0}, {-10.0, 0.0}, {-20.0, 5.0}}, 10.0);
  EXPECT_EQ(steps.duration_s(), 30.0);
  EXPECT_EQ(steps.at(0.0).fe_deg, 0.0);
  EXPECT_EQ(steps.at(9.999).fe_deg, 0.0);
  EXPECT_EQ(steps.at(10.0).fe_deg, -10.0);
  EXPECT_EQ(steps.at(25.0).ur_deg, 5.0);
  EXPECT_EQ(steps.at(99.0).fe_deg, -20.0);
  EXPECT_EQ(steps.at(-1.0).fe_deg, 0.0);
  EXPECT_EQ(steps.rate_at(15.0).fe_deg, 0.0);
  EXPECT_THROW(StepTrajectory({}, 10.0), std::invalid_argument);
  EXPECT_THROW(StepTrajectory({{NAN, 0.0}}, 10.0), std::invalid_argument);
  EXPECT_THROW(StepTrajectory({{0.0, 0.0}}, 0.0), std::invalid_argument);
}

// Section Spatial trajectory tracking: FE spans -40..30, UR -10..30, period 24 s, UR a quarter period behind; the
// rate is the derivative of the angle.
TEST(SinusoidTrajectory, SpansThePaperLimitsWithAQuarterPeriodLag) {
  const SinusoidTrajectory ellipse({});
  EXPECT_EQ(ellipse.duration_s(), 72.0);
  EXPECT_NEAR(ellipse.at(6.0).fe_deg, 30.0, 1e-12);  // FE peaks a quarter period in
  EXPECT_NEAR(ellipse.at(18.0).fe_deg, -40.0, 1e-12);
  EXPECT_NEAR(ellipse.at(12.0).ur_deg, 30.0, 1e-12);  // UR peaks a quarter period later
  EXPECT_NEAR(ellipse.at(0.0).ur_deg, -10.0, 1e-12);
  for (double t : {0.3, 5.0, 13.7, 40.0}) {
    const double h = 1e-5;
    EXPECT_NEAR(ellipse.rate_at(t).fe_deg, (ellipse.at(t + h).fe_deg - ellipse.at(t - h).fe_deg) / (2 * h), 1e-5);
    EXPECT_NEAR(ellipse.rate_at(t).ur_deg, (ellipse.at(t + h).ur_deg - ellipse.at(t - h).ur_deg) / (2 * h), 1e-5);
  }
  EXPECT_THROW(SinusoidTrajectory({.fe_min_deg = 10.0, .fe_max_deg = 0.0}), std::invalid_argument);
  EXPECT_THROW(SinusoidTrajectory({.period_s = 0.0}), std::invalid_argument);
  EXPECT_THROW(SinusoidTrajectory({.ur_max_deg = INFINITY}), std::invalid_argument);
}

}  // namespace
}  // namespace softwrist::control
