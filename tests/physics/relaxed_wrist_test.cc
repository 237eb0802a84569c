// The relaxed wrist's passive torque (physics/relaxed_wrist.h): the paper's linear wrist at its neutral parameters,
// the Riener & Edrich double-exponential stiffening towards the limits otherwise.

#include "physics/relaxed_wrist.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physics/units.h"

namespace softwrist::physics {
namespace {

using units::deg_to_rad;

const double kFlexion = deg_to_rad(80.9), kExtension = deg_to_rad(56.0);  // Table RoM, biological

TEST(RelaxedWrist, WithoutStiffeningItIsTheLinearWrist) {
  for (double angle : {-0.9, -0.3, 0.0, 0.4, 1.3}) {
    EXPECT_EQ(relaxed_wrist_torque(1.0, {}, kFlexion, kExtension, angle), -1.0 * angle);
    EXPECT_EQ(limit_stiffening_torque({.torque = 0.0}, kFlexion, kExtension, angle), 0.0);
  }
}

// A wrist stiffer towards one side: k (1 + a) towards flexion, k (1 - a) towards extension, continuous at neutral;
// a = 0 the linear wrist.
TEST(RelaxedWrist, AnAsymmetricWristIsStifferTowardsOneSide) {
  const double k = 1.2, a = 0.4;
  for (double angle : {-0.9, -0.3, 0.0, 0.4, 1.3}) {
    const double stiffness_here = angle > 0.0 ? k * (1.0 + a) : k * (1.0 - a);
    EXPECT_NEAR(relaxed_wrist_torque(k, {}, kFlexion, kExtension, angle, a), -stiffness_here * angle, 1e-15);
    EXPECT_EQ(relaxed_wrist_torque(k, {}, kFlexion, kExtension, angle, 0.0), -k * angle);
  }
  EXPECT_NEAR(relaxed_wrist_torque(k, {}, kFlexion, kExtension, 0.5, a) /
                  relaxed_wrist_torque(k, {}, kFlexion, kExtension, -0.5, a),
              -(1.0 + a) / (1.0 - a), 1e-12);
}

// Zero at neutral; at each limit it resists with the stated torque (within the offset that zeroes it at neutral,
// 0.1 %); it grows by e
// every e-folding angle near a limit; it never pushes a wrist further towards a limit.
TEST(RelaxedWrist, StiffeningVanishesAtNeutralAndResistsTowardsEitherLimit) {
  const LimitStiffening s{.torque = 2.0, .angle_scale = deg_to_rad(8.0)};
  EXPECT_NEAR(limit_stiffening_torque(s, kFlexion, kExtension, 0.0), 0.0, 1e-15);
  EXPECT_NEAR(limit_stiffening_torque(s, kFlexion, kExtension, kFlexion), -2.0, 5e-3);
  EXPECT_NEAR(limit_stiffening_torque(s, kFlexion, kExtension, -kExtension), 2.0, 5e-3);
  // Past a limit it holds its value there (the joint stop takes over).
  EXPECT_EQ(limit_stiffening_torque(s, kFlexion, kExtension, kFlexion + 0.3),
            limit_stiffening_torque(s, kFlexion, kExtension, kFlexion));
  const double near = limit_stiffening_torque(s, kFlexion, kExtension, kFlexion - deg_to_rad(8.0));
  const double nearer = limit_stiffening_torque(s, kFlexion, kExtension, kFlexion);
  EXPECT_NEAR(nearer / near, std::exp(1.0), 0.01);
  double previous = limit_stiffening_torque(s, kFlexion, kExtension, -kExtension);
  for (double angle = -kExtension + 0.01; angle <= kFlexion; angle += 0.01) {
    const double torque = limit_stiffening_torque(s, kFlexion, kExtension, angle);
    EXPECT_LT(torque, previous) << angle;  // strictly stiffening: its slope is negative everywhere
    EXPECT_LE(angle * torque, 1e-12) << angle;
    previous = torque;
  }
}

}  // namespace
}  // namespace softwrist::physics
