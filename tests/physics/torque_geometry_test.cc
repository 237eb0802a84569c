#include "physics/torque_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>
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

struct PathTolerances {
  double length, moment_arm, angles;
};
// The same regime, length and moment arm, and where it wraps the same wrap angle, within `tol`.
void expect_same_path(const MusclePath& path, const MusclePath& expected, PathTolerances tol, int deg) {
  ASSERT_EQ(path.regime, expected.regime) << deg;
  EXPECT_NEAR(path.length, expected.length, tol.length) << deg;
  EXPECT_NEAR(path.moment_arm, expected.moment_arm, tol.moment_arm) << deg;
  if (path.regime == Regime::kWrapping) {
    EXPECT_NEAR(path.wrap_angle, expected.wrap_angle, tol.angles) << deg;
  }
}

// The wrist circle's centre off the joint (WrapSurface, torque_geometry.h). At the joint, to within a nanometre, the
// general construction is the paper's path: issue 19's "each extension reduces to it at its neutral parameters".
TEST(MusclePathOffCentre, ANanometreOffTheJointIsThePapersPath) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  int wrapped = 0, straight = 0;
  for (const auto& [placement, r_w] : {std::pair{kDesign, kDesignRw}, {rig, 0.0399}}) {
    for (int deg = -80; deg <= 80; deg += 2) {
      const MusclePath paper = muscle_path(placement, r_w, deg_to_rad(deg));
      const MusclePath moved = muscle_path(placement, r_w, deg_to_rad(deg), WrapSurface{.x = 1e-9, .y = -1e-9});
      expect_same_path(moved, paper, {.length = 1e-8, .moment_arm = 1e-7, .angles = 1e-6}, deg);
      EXPECT_NEAR(moved.wrap_angle, paper.wrap_angle, 1e-6) << deg;  // straight too: phi is the circle's either way
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
  for (const WrapSurface centre : {WrapSurface{.x = 0.006, .y = 0.005}, WrapSurface{.x = -0.004, .y = -0.005}}) {
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

// A centre as far from O as the hand mount, or a circle that holds the hand mount at the joint's zero, is refused
// naming why; one the mount enters only as the wrist turns is not (hand_mount_clearance says at which angles).
TEST(MusclePathOffCentre, RejectsACentreTheHandMountIsInsideOrCircles) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  const double r2 = std::hypot(rig.d2, rig.w2);
  const auto message = [&](WrapSurface centre) {
    try {
      muscle_path(rig, 0.0399, 0.0, centre);
    } catch (const InvalidParameter& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(WrapSurface{.x = r2 + 0.001, .y = 0.0}).find("|OC|"), std::string::npos);
  EXPECT_NE(message(WrapSurface{.x = rig.d2, .y = 0.0}).find("|P2 - C| / r_w"), std::string::npos);  // 3.4 cm off
  EXPECT_EQ(message(WrapSurface{.x = r2 - 0.0399, .y = 0.0}), "accepted");  // 4.7 cm from the mount at zero
  EXPECT_THROW(muscle_path(rig, 0.0399, 0.0, WrapSurface{.x = std::nan(""), .y = 0.0}), InvalidParameter);
}

// The hand mount's least scaled distance from the surface's centre over |theta| <= reach, against a dense scan: the
// circle about O keeps R2 / r_w; a circle moved towards the hand is closest where the mount points at its centre.
TEST(HandMountClearance, IsTheLeastScaledDistanceOverTheReach) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  const double r2 = std::hypot(rig.d2, rig.w2);
  EXPECT_NEAR(hand_mount_clearance(rig, 0.0399, WrapSurface{}, std::numbers::pi), r2 / 0.0399, 1e-12);
  for (const WrapSurface s : {WrapSurface{.x = 0.05, .y = 0.0}, WrapSurface{.x = -0.008, .y = 0.008, .aspect = 1.6},
                              WrapSurface{.aspect = 0.6}}) {
    for (const double reach_deg : {10.0, 40.0, 95.0, 180.0}) {
      double scanned = INFINITY;
      for (int k = -200000; k <= 200000; ++k) {
        const Point p = hand_mount(rig, deg_to_rad(reach_deg) * k / 200000.0);
        scanned = std::min(scanned, std::hypot((p.x - s.x) / (s.aspect * 0.0399), (p.y - s.y) / 0.0399));
      }
      EXPECT_NEAR(hand_mount_clearance(rig, 0.0399, s, deg_to_rad(reach_deg)), scanned, 1e-9)
          << s.x << " " << s.aspect << " " << reach_deg;
    }
  }
  // The circle 5 cm towards the hand: R2 - |OC| = 3.96 cm from its centre where the mount points at it (-22 deg).
  EXPECT_NEAR(hand_mount_clearance(rig, 0.0399, WrapSurface{.x = 0.05}, std::numbers::pi), (r2 - 0.05) / 0.0399, 1e-9);
  EXPECT_GT(hand_mount_clearance(rig, 0.0399, WrapSurface{.x = 0.05}, deg_to_rad(10.0)), 1.0);
}

// Where the turning hand mount enters the surface (beyond the joint's reach), the path goes on through the mount's
// foot on it: length and moment arm continuous across the angle where it enters, finite at every angle to pi, on an
// ellipse longer along the forearm than across it (an ulnar muscle's mount 3.5 cm from O, 74 deg off the hand's axis,
// over an ellipse of semi-axis 3.7 cm along the forearm) and on a circle moved off the joint.
TEST(MusclePathBeyondTheReach, ContinuesThroughTheMountsFoot) {
  const Placement ulnar{.d1 = 0.211, .w1 = 0.071, .d2 = 0.010, .w2 = 0.034};
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  for (const auto& [placement, r_w, surface] : {std::tuple{ulnar, 0.0242, WrapSurface{.aspect = 1.53}},
                                                std::tuple{rig, 0.0399, WrapSurface{.x = 0.05, .y = 0.0}}}) {
    // Captured by name: clang 14 (the sanitizer build's compiler) cannot capture structured bindings.
    const auto inside = [&mount = placement, r = r_w, &wrap = surface](double theta) {
      const Point p = hand_mount(mount, theta);
      return std::hypot((p.x - wrap.x) / (wrap.aspect * r), (p.y - wrap.y) / r) < 1.0;
    };
    ASSERT_FALSE(inside(0.0));
    // The first angle below zero where the mount is inside, then the crossing by bisection.
    double lo = 0.0, hi = -std::numbers::pi;
    for (int deg = 0; deg >= -180; --deg) {
      if (inside(deg_to_rad(deg))) {
        hi = deg_to_rad(deg);
        break;
      }
      lo = deg_to_rad(deg);
    }
    ASSERT_TRUE(inside(hi));
    for (int i = 0; i < 60; ++i) (inside(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
    const MusclePath before = muscle_path(placement, r_w, lo + 1e-9, surface);
    const MusclePath after = muscle_path(placement, r_w, hi - 1e-9, surface);
    ASSERT_EQ(before.regime, Regime::kWrapping);
    EXPECT_NEAR(after.length, before.length, 1e-7);
    EXPECT_NEAR(after.moment_arm, before.moment_arm, 1e-5 * std::abs(before.moment_arm));
    // Over every angle, in quarter degrees: finite, the length without a step (at most a millimetre per step here;
    // atan2's cut once made it jump 17 cm at 106.5 deg), and MuJoCo's stand-in circle (spatial routing) a circle.
    MusclePath previous = muscle_path(placement, r_w, -std::numbers::pi, surface);
    for (int quarter = -719; quarter <= 720; ++quarter) {
      const double theta = deg_to_rad(0.25 * quarter);
      const MusclePath path = muscle_path(placement, r_w, theta, surface);
      EXPECT_TRUE(std::isfinite(path.length) && std::isfinite(path.moment_arm)) << 0.25 * quarter;
      EXPECT_LT(std::abs(path.length - previous.length), 0.001) << 0.25 * quarter << " deg";
      previous = path;
      const EquivalentCircle c = equivalent_circle(placement, r_w, surface, theta, path);
      EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && c.radius > 0.0 && c.radius < 1.0) << 0.25 * quarter;
    }
  }
}

// Deep inside the circle moved 5 cm towards the hand (the mount pointing at its centre, at -atan2(w2, d2)), the
// continued path by hand: the tangent from P1, the arc from Q1 to the foot, the foot to the mount; the moment arm
// along the circle at the foot.
TEST(MusclePathBeyondTheReach, InsideTheCircleIsTheArcToTheFootAndOn) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  constexpr double r_w = 0.0399;
  const WrapSurface surface{.x = 0.05, .y = 0.0};
  const double theta = -std::atan2(rig.w2, rig.d2);
  const Point p1 = forearm_mount(rig), p2 = hand_mount(rig, theta);
  const double r1 = std::hypot(p1.x - surface.x, p1.y - surface.y), r2 = std::hypot(p2.x - surface.x, p2.y);
  ASSERT_LT(r2, r_w);
  // Q1 on the muscle's side: P1's polar angle about C less the tangent's half-angle; the foot at P2's polar angle.
  const double q1 = std::atan2(p1.y - surface.y, p1.x - surface.x) - std::acos(r_w / r1);
  const double foot = std::atan2(p2.y - surface.y, p2.x - surface.x);
  const MusclePath path = muscle_path(rig, r_w, theta, surface);
  ASSERT_EQ(path.regime, Regime::kWrapping);
  EXPECT_NEAR(path.length, std::sqrt(r1 * r1 - r_w * r_w) + r_w * (q1 - foot) + (r_w - r2), 1e-12);
  EXPECT_NEAR(path.moment_arm, p2.x * std::cos(foot) + p2.y * std::sin(foot), 1e-12);
}

// A wrist surface that is not a circle (WrapSurface::aspect, an ellipse with semi-axes aspect r_w along the forearm
// and r_w across it). A hair from a circle (aspect 1 + 1e-9) it is the circle's path, about the joint and off it: the
// extension reduces to the paper's law at its neutral value.
TEST(MusclePathElliptic, AHairFromACircleIsTheCirclesPath) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  int wrapped = 0, straight = 0;
  for (const WrapSurface circle : {WrapSurface{}, WrapSurface{.x = 0.005, .y = 0.004}}) {
    WrapSurface ellipse = circle;
    ellipse.aspect = 1.0 + 1e-9;
    for (int deg = -80; deg <= 80; deg += 2) {
      const MusclePath expected = muscle_path(rig, 0.0399, deg_to_rad(deg), circle);
      const MusclePath path = muscle_path(rig, 0.0399, deg_to_rad(deg), ellipse);
      expect_same_path(path, expected, {.length = 1e-9, .moment_arm = 1e-9, .angles = 1e-7}, deg);
      EXPECT_NEAR(path.tangent_angle, expected.tangent_angle, 1e-7) << deg;
      (path.regime == Regime::kWrapping ? wrapped : straight) += 1;
    }
  }
  EXPECT_GT(wrapped, 20);
  EXPECT_GT(straight, 20);
}

// On an ellipse flatter along the forearm (aspect 1.5) and one rounder (0.7), off the joint: the moment arm about O
// is minus the length's derivative (virtual work, central differences) in both regimes, the length continuous, and
// both straight segments tangent to the ellipse (the ellipse's normal at Q1 and Q2 square to them).
TEST(MusclePathElliptic, MomentArmIsMinusTheLengthsDerivativeAndSegmentsAreTangent) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  constexpr double h = 1e-6, r_w = 0.0399;
  for (const WrapSurface surface : {WrapSurface{.x = 0.004, .y = 0.003, .aspect = 1.5}, WrapSurface{.aspect = 0.7}}) {
    const double a = surface.aspect * r_w, b = r_w;
    int wrapped = 0, straight = 0;
    for (int deg = -75; deg <= 75; ++deg) {
      const double theta = deg_to_rad(deg);
      const MusclePath path = muscle_path(rig, r_w, theta, surface);
      const double derivative =
          (muscle_path(rig, r_w, theta + h, surface).length - muscle_path(rig, r_w, theta - h, surface).length) /
          (2.0 * h);
      EXPECT_NEAR(path.moment_arm, -derivative, 1e-6) << deg << " deg, aspect " << surface.aspect;
      EXPECT_LT(std::abs(muscle_path(rig, r_w, deg_to_rad(deg + 1), surface).length - path.length), 0.002) << deg;
      if (path.regime == Regime::kStraight) {
        ++straight;
        continue;
      }
      ++wrapped;
      const TangentPoints q = tangent_points(rig, r_w, surface, theta, path);
      const Point p1 = forearm_mount(rig), p2 = hand_mount(rig, theta);
      for (const auto& [qx, qy, mx, my] :
           {std::tuple{q.q1x, q.q1y, p1.x, p1.y}, std::tuple{q.q2x, q.q2y, p2.x, p2.y}}) {
        const double ex = (qx - surface.x) / a, ey = (qy - surface.y) / b;
        EXPECT_NEAR(ex * ex + ey * ey, 1.0, 1e-12) << "on the ellipse, " << deg << " deg";
        const double nx = ex / a, ny = ey / b, tx = mx - qx, ty = my - qy;  // normal (gradient), segment
        EXPECT_NEAR((nx * tx + ny * ty) / (std::hypot(nx, ny) * std::hypot(tx, ty)), 0.0, 1e-9) << deg;
      }
    }
    EXPECT_GT(wrapped, 10);
    EXPECT_GT(straight, 10);
  }
}

// The equivalent circle (for MuJoCo's cylinders): a circle path around it, worked out here from tangent lengths and
// the arc, is as long as the elliptic path and leaves the hand mount along the same line (the same moment arm).
TEST(MusclePathElliptic, EquivalentCircleHasTheSameLengthAndMomentArm) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  constexpr double r_w = 0.0399;
  int wrapped = 0;
  for (const WrapSurface surface : {WrapSurface{.x = 0.004, .y = 0.003, .aspect = 1.5}, WrapSurface{.aspect = 0.7}}) {
    for (int deg = -75; deg <= 75; deg += 3) {
      const double theta = deg_to_rad(deg);
      const MusclePath path = muscle_path(rig, r_w, theta, surface);
      const EquivalentCircle c = equivalent_circle(rig, r_w, surface, theta, path);
      const Point p1 = forearm_mount(rig), p2 = hand_mount(rig, theta);
      if (path.regime == Regime::kStraight) {  // the segment misses the inscribed circle
        const double dx = p2.x - p1.x, dy = p2.y - p1.y;
        const double t = std::clamp(((c.x - p1.x) * dx + (c.y - p1.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
        EXPECT_GT(std::hypot(p1.x + t * dx - c.x, p1.y + t * dy - c.y), c.radius) << deg;
        continue;
      }
      ++wrapped;
      // Tangent points from each mount on the muscle's side (+y about the centre: P1 turns clockwise onto it).
      const auto tangent = [&](Point m, double side) {
        const double dx = m.x - c.x, dy = m.y - c.y, d = std::hypot(dx, dy);
        const double at = std::atan2(dy, dx) + side * std::acos(c.radius / d);
        return std::pair{std::sqrt(d * d - c.radius * c.radius), at};
      };
      const auto [l1, t1] = tangent(p1, -1.0);
      const auto [l2, t2] = tangent(p2, 1.0);
      double arc = t1 - t2;
      while (arc < 0.0) arc += 2.0 * std::numbers::pi;
      EXPECT_NEAR(l1 + c.radius * arc + l2, path.length, 1e-9) << deg << " deg, aspect " << surface.aspect;
      const double qx = c.x + c.radius * std::cos(t2), qy = c.y + c.radius * std::sin(t2);
      const double ux = qx - p2.x, uy = qy - p2.y;
      EXPECT_NEAR((p2.x * uy - p2.y * ux) / std::hypot(ux, uy), path.moment_arm, 1e-9) << deg;
    }
  }
  EXPECT_GT(wrapped, 20);
}

// An aspect outside [0.25, 4], or an ellipse that reaches the forearm mount, is refused naming why.
TEST(MusclePathElliptic, RejectsAnAspectOutOfRangeOrAMountInside) {
  const Placement rig = paper::torque_measurement_flexor(StretchMode::kNone).placement;
  EXPECT_THROW(muscle_path(rig, 0.0399, 0.0, WrapSurface{.aspect = 5.0}), InvalidParameter);
  EXPECT_THROW(muscle_path(rig, 0.0399, 0.0, WrapSurface{.aspect = std::nan("")}), InvalidParameter);
  try {
    muscle_path(rig, 0.0399, 0.0, WrapSurface{.x = -0.17, .y = 0.02, .aspect = 1.5});  // P1 - C scaled: 0.84
    FAIL();
  } catch (const InvalidParameter& e) {
    EXPECT_NE(std::string(e.what()).find("forearm mount P1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace softwrist::physics
