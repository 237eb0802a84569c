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

// The law's other shapes (mount_stretch.h, beyond the paper): every exponent passes through the paper's stretch at
// the reference pull F_r; n = 1 is linear in the pull; a preload F_p shifts the law to start at F_p.
TEST(MountStretch, OtherShapesKeepThePapersStretchAtTheReferencePull) {
  const double k = kPaperStiffness.forearm, papers = std::sqrt(kMountReferenceForce / 43.36e4);
  for (const double n : {1.0, 1.5, 3.0, 5.0}) {
    EXPECT_NEAR(mount_stretch(kMountReferenceForce, k, n), papers, 1e-15) << n;
    EXPECT_NEAR(mount_stretch(4.0 * kMountReferenceForce, k, n), papers * std::pow(4.0, 1.0 / n), 1e-14) << n;
  }
  EXPECT_NEAR(mount_stretch(2.0 * kMountReferenceForce, k, 1.0), 2.0 * papers, 1e-15);
  EXPECT_EQ(mount_stretch(7.9, k, 1.0, 8.0), 0.0);
  EXPECT_EQ(mount_stretch(8.0, k, 3.0, 8.0), 0.0);
  EXPECT_NEAR(mount_stretch(8.0 + kMountReferenceForce, k, 3.0, 8.0), papers, 1e-15);
  // n = 2 with a preload: the paper's law shifted to start at F_p.
  EXPECT_NEAR(mount_stretch(8.0 + 55.0, k, 2.0, 8.0), std::sqrt(55.0 / 43.36e4), 1e-15);
  const MountStiffness band{.forearm = k, .hand = kPaperStiffness.hand, .exponent = 1.0, .preload = 8.0};
  EXPECT_DOUBLE_EQ(total_mount_stretch(50.0, band),
                   mount_stretch(50.0, band.forearm, 1.0, 8.0) + mount_stretch(50.0, band.hand, 1.0, 8.0));
  EXPECT_FALSE(band.is_papers_law());
  EXPECT_TRUE(kPaperStiffness.is_papers_law());
}

// A linear band with a preload and a linear force law f(L) = k (L - L_slack): the self-consistent pull solves
// F = k (L - L_slack - b (F - F_p)) by hand, b the band's total compliance [m/N].
TEST(SolveMountStretch, SelfConsistentLinearBandWithPreloadMatchesHandSolution) {
  const double k = 2000.0, slack_length = 0.25, length = 0.31, preload = 8.0;
  const auto force_at_length = [&](double l) { return std::max(0.0, k * (l - slack_length)); };
  const MountStiffness band{
      .forearm = kPaperStiffness.forearm, .hand = kPaperStiffness.hand, .exponent = 1.0, .preload = preload};
  const double b = total_mount_stretch(preload + 1.0, band);  // the stretch of 1 N above the preload
  const double force = (k * (length - slack_length) + k * b * preload) / (1.0 + k * b);
  const auto solved = solve_mount_stretch(force_at_length, length, band, StretchMode::kSelfConsistent);
  EXPECT_NEAR(solved.force, force, 1e-8);
  EXPECT_NEAR(solved.mount_stretch, b * (force - preload), 1e-12);
  // Below the preload the mounts do not give: the unstretched pull.
  const auto slack = solve_mount_stretch(force_at_length, slack_length + 0.003, band, StretchMode::kSelfConsistent);
  EXPECT_NEAR(slack.force, 6.0, 1e-12);
  EXPECT_EQ(slack.mount_stretch, 0.0);
}

// Any shape: the fixed point satisfies both laws, F = f(L - s) and s = dx_1(F) + dx_2(F), and a stiffening strap
// (n > 2) gives less at high pulls than the paper's, so the muscle pulls more.
TEST(SolveMountStretch, SelfConsistentForAnyShapeSatisfiesBothLaws) {
  const auto force_at_length = [](double l) {
    return std::max(0.0, 3000.0 * (l - 0.2) - 40.0 * (l - 0.2) * (l - 0.2));
  };
  for (const double n : {1.0, 1.7, 2.0, 3.0, 5.0}) {
    for (const double preload : {0.0, 4.0}) {
      const MountStiffness shape{
          .forearm = kPaperStiffness.forearm, .hand = kPaperStiffness.hand, .exponent = n, .preload = preload};
      for (double length = 0.2; length < 0.4; length += 0.01) {
        const auto s = solve_mount_stretch(force_at_length, length, shape, StretchMode::kSelfConsistent);
        EXPECT_NEAR(s.force, force_at_length(length - s.mount_stretch), 1e-9 * (1.0 + s.force)) << n << " " << length;
        EXPECT_NEAR(s.mount_stretch, total_mount_stretch(s.force, shape), 1e-12) << n << " " << length;
        // One-shot: the stretch of the unstretched pull, then the force once more (and no more than the fixed point).
        const auto once = solve_mount_stretch(force_at_length, length, shape, StretchMode::kOneShot);
        EXPECT_NEAR(once.mount_stretch, total_mount_stretch(force_at_length(length), shape), 1e-15);
        EXPECT_LE(once.force, s.force + 1e-9) << n << " " << length;
      }
    }
  }
  const MountStiffness stiffening{.forearm = kPaperStiffness.forearm, .hand = kPaperStiffness.hand, .exponent = 4.0};
  const double at = 0.3;  // ~300 N unstretched: far above F_r, where n = 4 takes up less than n = 2
  EXPECT_GT(solve_mount_stretch(force_at_length, at, stiffening, StretchMode::kSelfConsistent).force,
            solve_mount_stretch(force_at_length, at, kPaperStiffness, StretchMode::kSelfConsistent).force);
}

// A linear band with a preload in series with mounts that keep the paper's law (MountStiffness::shaped_share): with
// a linear force law the self-consistent pull above the preload solves F = k (L - L_slack - c_q sqrt(F) - b (F - F_p)),
// c_q = (1 - s) c the paper's part's compliance and b = s c sqrt(F_r) / F_r the band's [m/N]; a quadratic in
// u = sqrt(F), (1 + k b) u^2 + k c_q u - k (L - L_slack + b F_p) = 0.
TEST(SolveMountStretch, ABandInSeriesWithThePapersMountsMatchesHandSolution) {
  const double k = 2000.0, slack_length = 0.25, length = 0.31, preload = 8.0, share = 0.4;
  const auto force_at_length = [&](double l) { return std::max(0.0, k * (l - slack_length)); };
  const MountStiffness mixed{.forearm = kPaperStiffness.forearm,
                             .hand = kPaperStiffness.hand,
                             .exponent = 1.0,
                             .preload = preload,
                             .shaped_share = share};
  const double c = mount_compliance(kPaperStiffness), c_q = (1.0 - share) * c;
  const double b = share * c * std::sqrt(kMountReferenceForce) / kMountReferenceForce;
  const double a2 = 1.0 + k * b, a1 = k * c_q, a0 = -k * (length - slack_length + b * preload);
  const double u = (-a1 + std::sqrt(a1 * a1 - 4.0 * a2 * a0)) / (2.0 * a2);
  ASSERT_GT(u * u, preload);
  const auto solved = solve_mount_stretch(force_at_length, length, mixed, StretchMode::kSelfConsistent);
  EXPECT_NEAR(solved.force, u * u, 1e-8);
  EXPECT_NEAR(solved.mount_stretch, c_q * u + b * (u * u - preload), 1e-12);
  // Below the preload only the paper's part gives: F = k (L - L_slack - c_q sqrt(F)).
  const double short_length = slack_length + 0.004;
  const double v = (-k * c_q + std::sqrt(k * k * c_q * c_q + 4.0 * k * (short_length - slack_length))) / 2.0;
  ASSERT_LT(v * v, preload);
  EXPECT_NEAR(solve_mount_stretch(force_at_length, short_length, mixed, StretchMode::kSelfConsistent).force, v * v,
              1e-9);
}

// The share's ends: s = 1 is the shaped law alone, s = 0 the paper's whatever the shape (and solved in closed form
// there: is_papers_law); at F_r with no preload every share stretches as the paper's; between them, the fixed point
// satisfies both laws for every shape.
TEST(SolveMountStretch, TheShapedShareRunsFromThePapersLawToTheShapedLaw) {
  const auto force_at_length = [](double l) {
    return std::max(0.0, 3000.0 * (l - 0.2) - 40.0 * (l - 0.2) * (l - 0.2));
  };
  MountStiffness shape{.forearm = kPaperStiffness.forearm, .hand = kPaperStiffness.hand, .exponent = 1.3};
  EXPECT_FALSE(shape.is_papers_law());
  for (const double share : {0.0, 0.25, 0.5, 0.9, 1.0}) {
    shape.shaped_share = share;
    EXPECT_EQ(shape.is_papers_law(), share == 0.0);
    EXPECT_NEAR(total_mount_stretch(kMountReferenceForce, shape),
                total_mount_stretch(kMountReferenceForce, kPaperStiffness), 1e-15);
    for (const double preload : {0.0, 6.0}) {
      shape.preload = preload;
      for (double length = 0.2; length < 0.4; length += 0.02) {
        const auto s = solve_mount_stretch(force_at_length, length, shape, StretchMode::kSelfConsistent);
        EXPECT_NEAR(s.force, force_at_length(length - s.mount_stretch), 1e-9 * (1.0 + s.force)) << share;
        EXPECT_NEAR(s.mount_stretch, total_mount_stretch(s.force, shape), 1e-12) << share;
        const auto once = solve_mount_stretch(force_at_length, length, shape, StretchMode::kOneShot);
        EXPECT_NEAR(once.mount_stretch, total_mount_stretch(force_at_length(length), shape), 1e-15);
        EXPECT_LE(once.force, s.force + 1e-9) << share << " " << length;
        const MountStiffness papers = kPaperStiffness, alone{.forearm = shape.forearm,
                                                             .hand = shape.hand,
                                                             .exponent = shape.exponent,
                                                             .preload = preload};
        const auto end =
            solve_mount_stretch(force_at_length, length, share == 0.0 ? papers : alone, StretchMode::kSelfConsistent);
        if (share == 0.0 || share == 1.0) {
          EXPECT_NEAR(s.force, end.force, 1e-9 * (1.0 + s.force)) << share;
        }
      }
    }
    shape.preload = 0.0;
  }
}

TEST(MountStretch, RejectsAnExponentOrPreloadOutOfRange) {
  EXPECT_THROW(mount_stretch(10.0, 1e5, 0.0), InvalidParameter);
  EXPECT_THROW(mount_stretch(10.0, 1e5, 9.0), InvalidParameter);
  EXPECT_THROW(mount_stretch(10.0, 1e5, std::nan("")), InvalidParameter);
  EXPECT_THROW(mount_stretch(10.0, 1e5, 2.0, -1.0), InvalidParameter);
  try {
    validate(MountStiffness{.forearm = 1e5, .hand = 1e6, .exponent = 0.2});
    ADD_FAILURE() << "no error";
  } catch (const InvalidParameter& e) {
    EXPECT_NE(std::string(e.what()).find("mount law exponent n"), std::string::npos) << e.what();
  }
  for (const double share : {-0.1, 1.5, std::nan("")}) {
    try {
      validate(MountStiffness{.forearm = 1e5, .hand = 1e6, .exponent = 1.0, .shaped_share = share});
      ADD_FAILURE() << "no error for share " << share;
    } catch (const InvalidParameter& e) {
      EXPECT_NE(std::string(e.what()).find("shaped share"), std::string::npos) << e.what();
    }
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
