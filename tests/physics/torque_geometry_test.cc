#include "physics/torque_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include <gtest/gtest.h>

#include "physics/errors.h"
#include "physics/paper_parameters.h"
#include "physics/units.h"

namespace softwrist::physics {
namespace {

using units::deg_to_rad;

struct Point {
  double x, y;
};
// The paper's frame (Fig. GeometricModel), written out independently of the library.
Point forearm_mount(const Placement& p) { return {-p.d1, p.w1}; }
Point hand_mount(const Placement& p, double theta) {
  return {p.d2 * std::cos(theta) - p.w2 * std::sin(theta), p.d2 * std::sin(theta) + p.w2 * std::cos(theta)};
}

// Eqn. straight_to_wrapping, read as the quadratic's discriminant (2ab)^2 - 4(1 + a^2)(b^2 - r_w^2) for the line
// y = a x + b through P1 and P2.
double discriminant(const Placement& p, double r_w, double theta) {
  const Point p1 = forearm_mount(p), p2 = hand_mount(p, theta);
  const double a = (p2.y - p1.y) / (p2.x - p1.x);
  const double b = p1.y - a * p1.x;
  return 4.0 * a * a * b * b - 4.0 * (1.0 + a * a) * (b * b - r_w * r_w);
}

const Placement kDesign = paper::kOptimizedPlacement;
constexpr double kDesignRw = paper::kDesignWristRadius;

// Eqn. tau1: the straight-line moment arm is the cross product of O->P2 with the unit vector P2->P1, and the length
// the distance P1P2.
TEST(MusclePath, StraightLineMomentArmIsEqnTau1CrossProduct) {
  for (double deg : {0.0, 10.0, 30.0, 60.0, 90.0}) {
    const double theta = deg_to_rad(deg);
    const auto path = muscle_path(kDesign, kDesignRw, theta);
    ASSERT_EQ(path.regime, Regime::kStraight) << deg;
    const Point p1 = forearm_mount(kDesign), p2 = hand_mount(kDesign, theta);
    const double length = std::hypot(p1.x - p2.x, p1.y - p2.y);
    EXPECT_NEAR(path.length, length, 1e-12);
    EXPECT_NEAR(path.moment_arm, (p2.x * (p1.y - p2.y) - p2.y * (p1.x - p2.x)) / length, 1e-12);
  }
}

// Eqn. tau2 read with psi + phi: the force leaves the wrist along the tangent at Q2, so the wrapped moment arm is
// exactly r_w ("In this range, the moment arm is constant"). Eqn. length is the two tangents plus the arc.
TEST(MusclePath, WrappedMomentArmIsWristRadiusAndLengthIsEqnLength) {
  for (double deg : {-5.0, -30.0, -65.4, -90.0}) {
    const auto path = muscle_path(kDesign, kDesignRw, deg_to_rad(deg));
    ASSERT_EQ(path.regime, Regime::kWrapping) << deg;
    EXPECT_NEAR(path.moment_arm, kDesignRw, 1e-12) << deg;
    const double r1 = std::hypot(kDesign.d1, kDesign.w1), r2 = std::hypot(kDesign.d2, kDesign.w2);
    EXPECT_NEAR(path.length,
                std::sqrt(r1 * r1 - kDesignRw * kDesignRw) + kDesignRw * path.wrap_angle +
                    std::sqrt(r2 * r2 - kDesignRw * kDesignRw),
                1e-12);
  }
}

// The printed Eqn. tau2 with cos/sin(phi - psi) puts Q2 off the tangent point: its moment arm falls short of r_w
// (by 0.44 % on the torque rig) and the torque would step at the transition. This documents why softwrist reads
// psi + phi, whose moment arm meets the straight-line one exactly.
TEST(MusclePath, PrintedTau2WithPhiMinusPsiWouldBreakContinuity) {
  const Placement p = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  const double r_w = 0.0399;
  const double theta = wrap_transition_angle(p, r_w) - 1e-9;
  const auto path = muscle_path(p, r_w, theta);
  ASSERT_EQ(path.regime, Regime::kWrapping);
  const double psi = path.tangent_angle, phi = path.wrap_angle;
  ASSERT_GT(std::abs(psi), 0.02) << "psi must be clearly non-zero for the comparison to mean anything";
  const Point p2 = hand_mount(p, theta);
  const double q = phi - psi;  // as printed
  const double p2q2 = std::hypot(r_w * std::sin(q) - p2.x, r_w * std::cos(q) - p2.y);
  const double printed_arm = r_w / p2q2 * (p2.x * std::cos(q) - p2.y * std::sin(q));
  const double straight_arm = muscle_path(p, r_w, theta + 2e-9).moment_arm;
  EXPECT_NEAR(path.moment_arm, straight_arm, 1e-9);
  EXPECT_NEAR(path.moment_arm, r_w, 1e-12);
  EXPECT_GT(std::abs(printed_arm - straight_arm), 1e-4);  // 0.18 mm against a 1e-9 match
  EXPECT_NEAR(printed_arm / r_w, 1.0 - 0.0044, 0.0005);
}

// Section Exosuit torque model: the transition "occurs when the line along the two mounting points changes from
// being disjoint to becoming tangent to the circle", i.e. D = 0; length and moment arm are continuous there.
TEST(MusclePath, TransitionIsWhereDiscriminantVanishesAndPathIsContinuous) {
  const std::pair<Placement, double> cases[] = {
      {kDesign, kDesignRw}, {paper::torque_measurement_flexor(StretchMode::kNone).placement, 0.0399}};
  for (const auto& [p, r_w] : cases) {
    const double theta = wrap_transition_angle(p, r_w);
    const auto wrapped = muscle_path(p, r_w, theta - 1e-9);
    const auto straight = muscle_path(p, r_w, theta + 1e-9);
    EXPECT_EQ(wrapped.regime, Regime::kWrapping);
    EXPECT_EQ(straight.regime, Regime::kStraight);
    EXPECT_NEAR(wrapped.length, straight.length, 1e-8);
    EXPECT_NEAR(wrapped.moment_arm, straight.moment_arm, 1e-7);
    const double scale = discriminant(p, r_w, theta + 0.1);
    EXPECT_NEAR(discriminant(p, r_w, theta) / std::abs(scale), 0.0, 1e-6);
    EXPECT_GT(discriminant(p, r_w, theta - 0.01), 0.0);  // cuts the wrist: wraps
    EXPECT_LT(discriminant(p, r_w, theta + 0.01), 0.0);  // clear of the wrist: straight
  }
}

// The discriminant alone does not say whether the muscle touches the wrist: for the ulnar muscle of Table RoM at
// 80 deg the line through both mounts meets the wrist circle (D > 0) beyond the hand mount, while the muscle itself
// (the segment P1P2) stays clear of it and runs straight.
TEST(MusclePath, DiscriminantCanReportAnIntersectionTheMuscleNeverMakes) {
  const Placement ulnar = paper::rom_table()[2].placement;
  const double r_w = paper::kRomWristRadius;
  const double theta = deg_to_rad(80.0);
  EXPECT_GT(discriminant(ulnar, r_w, theta), 0.0);
  const auto path = muscle_path(ulnar, r_w, theta);
  EXPECT_EQ(path.regime, Regime::kStraight);
  // Closest point of the segment P1P2 to O lies outside the wrist.
  const Point p1 = forearm_mount(ulnar), p2 = hand_mount(ulnar, theta);
  const double dx = p2.x - p1.x, dy = p2.y - p1.y;
  const double t = std::clamp(-(p1.x * dx + p1.y * dy) / (dx * dx + dy * dy), 0.0, 1.0);
  EXPECT_GT(std::hypot(p1.x + t * dx, p1.y + t * dy), r_w);
}

// Section Parameter optimization: with the optimized placement (Table optimized_parameters) the flexor wraps "from
// full extension to -1 deg of extension". Our transition is within 0.5 deg of that.
TEST(MusclePath, OptimizedPlacementStopsWrappingNearMinusOneDegree) {
  EXPECT_NEAR(units::rad_to_deg(wrap_transition_angle(kDesign, kDesignRw)), -1.0, 0.5);
}

TEST(MusclePath, RejectsMountsInsideTheWristAndBadAngles) {
  try {
    muscle_path(paper::rom_table()[2].placement, 0.0399, 0.0);  // ulnar hand mount R2 = 3.54 cm < r_w
    FAIL();
  } catch (const InvalidParameter& e) {
    EXPECT_NE(std::string(e.what()).find("R2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(muscle_path(kDesign, 0.0, 0.0), InvalidParameter);
  EXPECT_THROW(muscle_path(kDesign, kDesignRw, std::nan("")), InvalidParameter);
  EXPECT_THROW(muscle_path(kDesign, kDesignRw, 4.0), InvalidParameter);
  EXPECT_THROW(muscle_path(Placement{.d1 = -0.1, .w1 = 0.03, .d2 = 0.05, .w2 = 0.02}, 0.02, 0.0), InvalidParameter);
  EXPECT_THROW(muscle_path(Placement{.d1 = 0.1, .w1 = std::nan(""), .d2 = 0.05, .w2 = 0.02}, 0.02, 0.0),
               InvalidParameter);
}

// The wrist circle's centre off the joint (WrapCentre, torque_geometry.h). At the joint, to within a nanometre, the
// general construction is the paper's path: issue 19's "each extension reduces to it at its neutral parameters".
TEST(MusclePathOffCentre, ANanometreOffTheJointIsThePapersPath) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  int wrapped = 0, straight = 0;
  for (const auto& [placement, r_w] : {std::pair{kDesign, kDesignRw}, {rig, 0.0399}}) {
    for (int deg = -80; deg <= 80; deg += 2) {
      const MusclePath paper = muscle_path(placement, r_w, deg_to_rad(deg));
      const MusclePath moved = muscle_path(placement, r_w, deg_to_rad(deg), WrapCentre{.x = 1e-9, .y = -1e-9});
      ASSERT_EQ(moved.regime, paper.regime) << deg;
      EXPECT_NEAR(moved.length, paper.length, 1e-8) << deg;
      EXPECT_NEAR(moved.moment_arm, paper.moment_arm, 1e-7) << deg;
      EXPECT_NEAR(moved.wrap_angle, paper.wrap_angle, 1e-6) << deg;
      (paper.regime == Regime::kWrapping ? wrapped : straight) += 1;
    }
  }
  EXPECT_GT(wrapped, 20);
  EXPECT_GT(straight, 20);
}

// Virtual work: a muscle pulling with force F along its path turns the joint with F times -dL/dtheta, so the moment
// arm about O is minus the path length's derivative, whichever point the path wraps around. Checked by central
// differences with the circle moved 6 mm towards the hand and 5 mm in either direction across the forearm, in both
// regimes; and the length is continuous where the regime changes.
TEST(MusclePathOffCentre, MomentArmAboutTheJointIsMinusTheLengthsDerivative) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  constexpr double h = 1e-6;
  for (const WrapCentre centre : {WrapCentre{.x = 0.006, .y = 0.005}, WrapCentre{.x = -0.004, .y = -0.005}}) {
    int wrapped = 0, straight = 0;
    for (int deg = -75; deg <= 75; ++deg) {
      const double theta = deg_to_rad(deg);
      const MusclePath path = muscle_path(rig, 0.0399, theta, centre);
      const double derivative =
          (muscle_path(rig, 0.0399, theta + h, centre).length - muscle_path(rig, 0.0399, theta - h, centre).length) /
          (2.0 * h);
      EXPECT_NEAR(path.moment_arm, -derivative, 1e-6) << deg << " deg, centre " << centre.x << ", " << centre.y;
      (path.regime == Regime::kWrapping ? wrapped : straight) += 1;
      const MusclePath next = muscle_path(rig, 0.0399, deg_to_rad(deg + 1), centre);
      EXPECT_LT(std::abs(next.length - path.length), 0.002) << deg;  // no jump at the transition
    }
    EXPECT_GT(wrapped, 10);
    EXPECT_GT(straight, 10);
    // Straight, the path is the segment P1P2 whatever the centre.
    const double theta = deg_to_rad(75.0);
    const Point p1 = forearm_mount(rig), p2 = hand_mount(rig, theta);
    EXPECT_NEAR(muscle_path(rig, 0.0399, theta, centre).length, std::hypot(p2.x - p1.x, p2.y - p1.y), 1e-12);
  }
}

// A circle moved so far that the turning hand mount would come within r_w of its centre is refused, naming why.
TEST(MusclePathOffCentre, RejectsACentreTheHandMountWouldEnter) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  const double r2 = std::hypot(rig.d2, rig.w2);
  try {
    muscle_path(rig, 0.0399, 0.0, WrapCentre{.x = r2 - 0.0399, .y = 0.0});
    FAIL();
  } catch (const InvalidParameter& e) {
    EXPECT_NE(std::string(e.what()).find("R2 - |OC|"), std::string::npos) << e.what();
  }
  EXPECT_THROW(muscle_path(rig, 0.0399, 0.0, WrapCentre{.x = std::nan(""), .y = 0.0}), InvalidParameter);
}

}  // namespace
}  // namespace softwrist::physics
