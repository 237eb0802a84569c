// Mount positions for the motion-capture torque method (Section Torque applied by the exosuit).

#include "physics/mount_points.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physics/muscle_torque.h"
#include "physics/paper_parameters.h"
#include "physics/units.h"

namespace softwrist::physics {
namespace {

TEST(MountPoints, PlacementRoundTripsThroughThePositions) {
  const Placement p{.d1 = 0.1947, .w1 = 0.0493, .d2 = 0.083, .w2 = 0.0338};
  for (double deg = -80; deg <= 90; deg += 10) {
    const Placement back = placement_from_mount_points(mount_points(p, units::deg_to_rad(deg)), units::deg_to_rad(deg));
    EXPECT_NEAR(back.d1, p.d1, 1e-12);
    EXPECT_NEAR(back.w1, p.w1, 1e-12);
    EXPECT_NEAR(back.d2, p.d2, 1e-12);
    EXPECT_NEAR(back.w2, p.w2, 1e-12);
  }
}

// Mounts moved by Eqn. fabric_stretching along the line of action: the placement read from those positions,
// modeled without stretching, gives the torque of the stretched model (same moment arm, length shorter by
// dx1 + dx2), straight and wrapped (Table torque_measurement_parameters).
TEST(MountPoints, StretchedPositionsGiveTheStretchedModelsTorque) {
  const Muscle stretched = paper::torque_measurement_flexor(StretchMode::kSelfConsistent);
  Muscle fixed = stretched;
  fixed.stretch_mode = StretchMode::kNone;
  int wrapped = 0;
  for (double deg = -67.5; deg <= 90.0; deg += 7.5) {
    const double angle = units::deg_to_rad(deg);
    const MuscleState truth = muscle_state(stretched, angle, 137e3);
    const MountPoints points = stretched_mount_points(stretched.placement, stretched.wrist_radius, angle, truth.force,
                                                      stretched.mount_stiffness);
    const double moved =
        std::hypot(points.forearm.x + stretched.placement.d1, points.forearm.y - stretched.placement.w1);
    EXPECT_NEAR(moved, mount_stretch(truth.force, stretched.mount_stiffness.forearm), 1e-12);
    fixed.placement = placement_from_mount_points(points, angle);
    const MuscleState measured = muscle_state(fixed, angle, 137e3);
    EXPECT_NEAR(measured.torque, truth.torque, 1e-6 + 1e-6 * std::abs(truth.torque)) << deg;
    wrapped += truth.regime == Regime::kWrapping;
  }
  EXPECT_GT(wrapped, 2);
}

}  // namespace
}  // namespace softwrist::physics
