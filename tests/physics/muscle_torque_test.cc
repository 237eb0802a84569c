#include "physics/muscle_torque.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physics/errors.h"
#include "physics/fpam_force.h"
#include "physics/paper_parameters.h"
#include "physics/range_of_motion.h"
#include "physics/units.h"

namespace softwrist::physics {
namespace {

using units::deg_to_rad;
using units::rad_to_deg;

// Section Parameter optimization (Fig. ParameterOptimizationResult): r0 = 1.23 cm, eps_max = 0.28, 137 kPa,
// r_w = 2 cm, L0 from Eqn. length at -65.4 deg, d1 = 22, w1 = 3.5, d2 = 9, w2 = 1.5 cm. The torque "continues
// decreasing until it reaches zero at 72 deg".
TEST(MuscleTorque, OptimizedFlexorTorqueReachesZeroNear72Degrees) {
  const Muscle flexor = paper::design_optimum_flexor();
  const auto limit = joint_limit(flexor, 137e3, deg_to_rad(90.0));
  ASSERT_TRUE(limit.has_value());
  EXPECT_NEAR(rad_to_deg(*limit), 72.0, 0.5);
  // Just below the limit it still pulls; from the limit on it applies none.
  EXPECT_GT(muscle_state(flexor, *limit - deg_to_rad(1.0), 137e3).torque, 0.0);
  EXPECT_EQ(muscle_state(flexor, *limit + deg_to_rad(1.0), 137e3).torque, 0.0);
}

// The same curve's shape as the paper describes it: wrapped from full extension to about -1 deg with a constant
// moment arm, the torque falling linearly towards the transition; then "the torque increases at the early stage of
// wrist flexion due to the sudden increase in the moment arm".
TEST(MuscleTorque, OptimizedFlexorCurveHasThePapersShape) {
  const Muscle flexor = paper::design_optimum_flexor();
  const auto at = [&](double deg) { return muscle_state(flexor, deg_to_rad(deg), 137e3); };
  EXPECT_EQ(at(-65.4).regime, Regime::kWrapping);
  EXPECT_NEAR(at(-65.4).contraction_ratio, 0.0, 1e-12) << "L0 is Eqn. length at -65.4 deg";
  EXPECT_NEAR(at(-30.0).torque, at(-30.0).force * paper::kDesignWristRadius, 1e-12);
  EXPECT_GT(at(-60.0).torque, at(-30.0).torque);
  EXPECT_GT(at(-30.0).torque, at(-2.0).torque);
  EXPECT_GT(at(20.0).torque, at(0.0).torque);
}

// Torque is continuous across the straight/wrapping transition (Eqns. tau1 and tau2 meet), at every pressure, with
// and without stretching.
TEST(MuscleTorque, ContinuousAcrossTheTransition) {
  for (StretchMode mode : {StretchMode::kNone, StretchMode::kOneShot, StretchMode::kSelfConsistent}) {
    const Muscle flexor = paper::torque_measurement_flexor(mode);
    const double theta = wrap_transition_angle(flexor.placement, flexor.wrist_radius);
    for (double pressure : paper::kMeasurementPressures) {
      const auto before = muscle_state(flexor, theta - 1e-9, pressure);
      const auto after = muscle_state(flexor, theta + 1e-9, pressure);
      EXPECT_EQ(before.regime, Regime::kWrapping);
      EXPECT_EQ(after.regime, Regime::kStraight);
      EXPECT_NEAR(before.torque, after.torque, 1e-6) << to_string(mode) << " " << pressure;
    }
  }
}

// Section Torque applied by the exosuit: modeling the mounts' stretch lowers the predicted torque (the paper's MAE
// fell from 1.111 to 0.283 Nm because the fixed-placement model overestimated). At every measured angle and
// pressure of the rig (Table torque_measurement_parameters), stretching never raises the torque, and lowers it
// wherever the muscle pulls.
TEST(MuscleTorque, StretchingLowersTorqueOnTheTorqueRig) {
  const Muscle fixed = paper::torque_measurement_flexor(StretchMode::kNone);
  const Muscle stretched = paper::torque_measurement_flexor(StretchMode::kSelfConsistent);
  int lowered = 0;
  for (double deg = -67.5; deg <= 90.0; deg += 22.5) {
    for (double pressure : paper::kMeasurementPressures) {
      const auto a = muscle_state(fixed, deg_to_rad(deg), pressure);
      const auto b = muscle_state(stretched, deg_to_rad(deg), pressure);
      EXPECT_LE(b.torque, a.torque + 1e-12) << deg << " " << pressure;
      if (a.torque > 0.0) {
        EXPECT_LT(b.torque, a.torque) << deg << " " << pressure;
        ++lowered;
      }
    }
  }
  EXPECT_GT(lowered, 10);
}

// The self-consistent state is a fixed point of Eqn. force and Eqn. fabric_stretching together.
TEST(MuscleTorque, SelfConsistentStateSatisfiesBothLaws) {
  const Muscle flexor = paper::torque_measurement_flexor(StretchMode::kSelfConsistent);
  const auto state = muscle_state(flexor, deg_to_rad(22.5), 137e3);
  ASSERT_GT(state.force, 0.0);
  EXPECT_NEAR(state.mount_stretch, total_mount_stretch(state.force, flexor.mount_stiffness), 1e-10);
  EXPECT_NEAR(state.force,
              fpam_force(flexor.fpam, 137e3, contraction_ratio(state.effective_length, flexor.rest_length)), 1e-6);
}

TEST(MuscleTorque, RejectsInvalidMuscles) {
  Muscle muscle = paper::design_optimum_flexor();
  muscle.rest_length = -0.3;
  EXPECT_THROW(muscle_state(muscle, 0.0, 100e3), InvalidParameter);
  muscle = paper::design_optimum_flexor();
  muscle.stretch_mode = StretchMode::kSelfConsistent;  // with K1 = K2 = 0
  EXPECT_THROW(muscle_state(muscle, 0.0, 100e3), InvalidParameter);
  EXPECT_THROW(muscle_state(paper::design_optimum_flexor(), 0.0, -5.0), InvalidParameter);
}

}  // namespace
}  // namespace softwrist::physics
