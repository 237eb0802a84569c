#include "physics/mount_stretch.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physics/units.h"

namespace softwrist::physics {
namespace {

// Table torque_measurement_parameters, in SI.
const MountStiffness kPaperStiffness{units::n_per_cm2_to_n_per_m2(-43.36), units::n_per_cm2_to_n_per_m2(-1097.50)};

// Eqn. fabric_stretching: F = K dx^2, with |K| (the table's K are negative, see mount_stretch.h).
TEST(MountStretch, SatisfiesEqnFabricStretching) {
  for (double force : {0.0, 1.0, 50.0, 170.0}) {
    const double dx1 = mount_stretch(force, kPaperStiffness.forearm);
    const double dx2 = mount_stretch(force, kPaperStiffness.hand);
    EXPECT_NEAR(43.36e4 * dx1 * dx1, force, 1e-9);
    EXPECT_NEAR(1097.50e4 * dx2 * dx2, force, 1e-9);
    EXPECT_DOUBLE_EQ(total_mount_stretch(force, kPaperStiffness), dx1 + dx2);
  }
  // 100 N stretch the forearm mount by sqrt(100 / 43.36) = 1.519 cm.
  EXPECT_NEAR(units::m_to_cm(mount_stretch(100.0, kPaperStiffness.forearm)), 1.519, 0.001);
}

// A linear force law f(L) = k (L - L_slack) lets the self-consistent fixed point be solved by hand:
// F = k (L - L_slack - c sqrt(F)) is a quadratic in u = sqrt(F).
TEST(SolveMountStretch, SelfConsistentMatchesHandSolvedQuadratic) {
  const double k = 2000.0, slack_length = 0.25, length = 0.31;
  const auto force_at_length = [&](double l) { return std::max(0.0, k * (l - slack_length)); };
  const double c = 1.0 / std::sqrt(43.36e4) + 1.0 / std::sqrt(1097.50e4);
  const double u = (-k * c + std::sqrt(k * k * c * c + 4.0 * k * (length - slack_length))) / 2.0;
  const auto solved = solve_mount_stretch(force_at_length, length, kPaperStiffness, StretchMode::kSelfConsistent);
  EXPECT_NEAR(solved.force, u * u, 1e-8);
  EXPECT_NEAR(solved.mount_stretch, c * u, 1e-12);
  EXPECT_NEAR(force_at_length(length - solved.mount_stretch), solved.force, 1e-8);
}

// The paper's one-shot version: the stretch from the unstretched force, then the force once more.
TEST(SolveMountStretch, OneShotUsesTheForceAtTheInitialPlacement) {
  const auto force_at_length = [](double l) { return std::max(0.0, 2000.0 * (l - 0.25)); };
  const double initial = force_at_length(0.31);
  const double stretch = total_mount_stretch(initial, kPaperStiffness);
  const auto solved = solve_mount_stretch(force_at_length, 0.31, kPaperStiffness, StretchMode::kOneShot);
  EXPECT_DOUBLE_EQ(solved.mount_stretch, stretch);
  EXPECT_DOUBLE_EQ(solved.force, force_at_length(0.31 - stretch));
}

// One-shot stretches by the largest force, so it undershoots the fixed point, which itself lies below the
// unstretched force.
TEST(SolveMountStretch, OneShotLeqSelfConsistentLeqUnstretched) {
  const auto force_at_length = [](double l) {
    return std::max(0.0, 3000.0 * (l - 0.2) - 40.0 * (l - 0.2) * (l - 0.2));
  };
  for (double length = 0.2; length < 0.4; length += 0.01) {
    const double none = solve_mount_stretch(force_at_length, length, kPaperStiffness, StretchMode::kNone).force;
    const double self =
        solve_mount_stretch(force_at_length, length, kPaperStiffness, StretchMode::kSelfConsistent).force;
    const double once = solve_mount_stretch(force_at_length, length, kPaperStiffness, StretchMode::kOneShot).force;
    EXPECT_LE(once, self + 1e-9) << length;
    EXPECT_LE(self, none + 1e-9) << length;
  }
}

TEST(MountStretch, RejectsZeroOrNonFiniteStiffnessAndParsesModes) {
  EXPECT_THROW(mount_stretch(10.0, 0.0), InvalidParameter);
  EXPECT_THROW(mount_stretch(10.0, std::nan("")), InvalidParameter);
  EXPECT_THROW(mount_stretch(-1.0, 1e5), InvalidParameter);
  const auto force_at_length = [](double l) { return 1000.0 * l; };
  EXPECT_THROW(solve_mount_stretch(force_at_length, 0.3, MountStiffness{0.0, 1e5}, StretchMode::kOneShot),
               InvalidParameter);
  EXPECT_NO_THROW(solve_mount_stretch(force_at_length, 0.3, MountStiffness{0.0, 1e5}, StretchMode::kNone));
  EXPECT_EQ(parse_stretch_mode("selfconsistent"), StretchMode::kSelfConsistent);
  EXPECT_EQ(parse_stretch_mode("oneshot"), StretchMode::kOneShot);
  EXPECT_EQ(parse_stretch_mode("none"), StretchMode::kNone);
  EXPECT_FALSE(parse_stretch_mode("self").has_value());
  EXPECT_STREQ(to_string(StretchMode::kOneShot), "oneshot");
}

}  // namespace
}  // namespace softwrist::physics
