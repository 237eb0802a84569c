#include "physics/range_of_motion.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physics/errors.h"
#include "physics/paper_parameters.h"
#include "physics/units.h"

namespace softwrist::physics {
namespace {

using units::deg_to_rad;
using units::rad_to_deg;

// Eqn. tau1's L, written out independently of the library.
double straight_length(const Placement& p, double theta) {
  return std::hypot(-p.d1 - p.d2 * std::cos(theta) + p.w2 * std::sin(theta),
                    p.w1 - p.d2 * std::sin(theta) - p.w2 * std::cos(theta));
}

// Table RoM with the 137 kPa parameters (Section Range of motion: r0 and eps_max of the flexor at 137 kPa): a
// muscle alone stops where its torque reaches zero, and that is where its length reaches L0 (1 - eps_max): the
// pressure force vanishes there (Eqn. fiber_orientation) and the fabric term already did (eps_max > epsilon_0).
TEST(JointLimit, TableRomLimitsAreWhereLengthReachesL0TimesOneMinusEpsMax) {
  const double eps_max = 0.277;
  for (const auto& entry : paper::rom_table()) {
    const Muscle muscle = paper::rom_muscle(entry);
    const auto limit = joint_limit(muscle, 137e3, deg_to_rad(90.0));
    ASSERT_TRUE(limit.has_value()) << entry.direction;
    EXPECT_GT(*limit, 0.0) << entry.direction;
    EXPECT_EQ(muscle_path(muscle.placement, muscle.wrist_radius, *limit).regime, Regime::kStraight);
    EXPECT_NEAR(straight_length(muscle.placement, *limit), entry.rest_length * (1.0 - eps_max), 1e-9)
        << entry.direction << " limit " << rad_to_deg(*limit) << " deg";
  }
}

// The limits fall in the straight-line regime, so the wrist radius (which Table RoM does not give) cannot change
// them as long as it is a valid radius for every mount.
TEST(JointLimit, TableRomLimitsDoNotDependOnTheUnstatedWristRadius) {
  for (const auto& entry : paper::rom_table()) {
    Muscle muscle = paper::rom_muscle(entry);
    const double reference = *joint_limit(muscle, 137e3, deg_to_rad(90.0));
    muscle.wrist_radius = 0.01;
    EXPECT_NEAR(*joint_limit(muscle, 137e3, deg_to_rad(90.0)), reference, 1e-9) << entry.direction;
  }
}

TEST(JointLimit, NulloptWhenStillPullingAtTheEndOfTheSearch) {
  EXPECT_FALSE(joint_limit(paper::design_optimum_flexor(), 137e3, deg_to_rad(30.0)).has_value());
  EXPECT_THROW(joint_limit(paper::design_optimum_flexor(), 137e3, -1.0), InvalidParameter);
}

// A deflated muscle that is slack at the neutral wrist (contraction >= epsilon_0) moves nothing: limit 0.
TEST(JointLimit, ZeroForASlackDeflatedMuscle) {
  const Muscle flexion = paper::rom_muscle(paper::rom_table()[0]);
  EXPECT_EQ(*joint_limit(flexion, 0.0, deg_to_rad(90.0)), 0.0);
}

}  // namespace
}  // namespace softwrist::physics
