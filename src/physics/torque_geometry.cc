#include "physics/torque_geometry.h"

#include <cmath>
#include <numbers>

#include "physics/errors.h"
#include "physics/plausible_ranges.h"

namespace softwrist::physics {

const char* to_string(Regime regime) { return regime == Regime::kWrapping ? "wrapping" : "straight"; }

void validate(const Placement& placement, double wrist_radius, WrapCentre centre) {
  require_positive("placement d1 [m]", placement.d1);
  require_non_negative("placement w1 [m]", placement.w1);
  require_positive("placement d2 [m]", placement.d2);
  require_non_negative("placement w2 [m]", placement.w2);
  require_positive("wrist_radius r_w [m]", wrist_radius);
  require_finite("wrap centre x [m]", centre.x);
  require_finite("wrap centre y [m]", centre.y);
  for (const auto& [name, value] : {std::pair{"placement d1 [m]", placement.d1},
                                    {"placement w1 [m]", placement.w1},
                                    {"placement d2 [m]", placement.d2},
                                    {"placement w2 [m]", placement.w2},
                                    {"wrist_radius r_w [m]", wrist_radius},
                                    {"wrap centre x [m]", std::abs(centre.x)},
                                    {"wrap centre y [m]", std::abs(centre.y)}}) {
    require(value <= plausible::kMaxLength, name, value, "must be at most 10 (m; the arm is not that long)");
  }
  const double r1 = std::hypot(placement.d1 + centre.x, placement.w1 - centre.y);  // |P1 - C|
  require(r1 > wrist_radius, "forearm mount distance R1 [m]", r1,
          "must exceed the wrist radius r_w (mount outside the wrist)");
  // The hand mount turns about O: its closest approach to C is R2 - |OC|.
  const double closest = std::hypot(placement.d2, placement.w2) - std::hypot(centre.x, centre.y);
  require(closest > wrist_radius,
          centre.at_joint() ? "hand mount distance R2 [m]" : "hand mount distance R2 - |OC| [m]", closest,
          "must exceed the wrist radius r_w (mount outside the wrist at every angle)");
}

namespace {

// psi of Eqn. parameters2. Q1 is the tangent point from P1 on the muscle's side: P1 lies at polar angle
// atan2(w1, -d1) about C, and the tangent from it touches the circle acos(r_w/R1) closer to +y; psi is measured from y.
double tangent_angle(const Placement& placement, double r_w, WrapCentre centre = {}) {
  const double x = -placement.d1 - centre.x, y = placement.w1 - centre.y;
  const double q1_polar = std::atan2(y, x) - std::acos(r_w / std::hypot(x, y));
  return std::numbers::pi / 2.0 - q1_polar;
}

// Eqn. tau1: the straight segment P1P2 (P2 = (p2x, p2y) at an angle of cosine c and sine s), whatever the wrist
// circle, which it does not touch (sqrt rather than std::hypot: PlacementGeometry::at says why).
void set_straight(MusclePath& path, const Placement& p, double c, double s, double p2x, double p2y) {
  path.regime = Regime::kStraight;
  const double ux = -p.d1 - p2x, uy = p.w1 - p2y;
  path.length = std::sqrt(ux * ux + uy * uy);
  path.moment_arm = ((p.d1 * p.d2 - p.w1 * p.w2) * s + (p.d1 * p.w2 + p.d2 * p.w1) * c) / path.length;
}

// Eqn. parameters2 at joint angle 0: phi(theta) = phi0 - theta.
double wrap_angle_at_zero(const Placement& placement, double r_w, double psi) {
  const double r2 = std::hypot(placement.d2, placement.w2);
  return std::numbers::pi / 2.0 - (psi + std::acos(r_w / r2) + std::asin(placement.w2 / r2));
}

}  // namespace

double wrap_transition_angle(const Placement& placement, double wrist_radius) {
  validate(placement, wrist_radius);
  return wrap_angle_at_zero(placement, wrist_radius, tangent_angle(placement, wrist_radius));
}

PlacementGeometry::PlacementGeometry(const Placement& placement, double wrist_radius, WrapCentre centre)
    : placement_(placement), centre_(centre), wrist_radius_(wrist_radius) {
  validate(placement, wrist_radius, centre);
  const double x1 = placement.d1 + centre.x, y1 = placement.w1 - centre.y;  // |P1 - C| = |(x1, y1)|
  tangent_length1_ = std::sqrt(x1 * x1 + y1 * y1 - wrist_radius * wrist_radius);
  tangent_length2_ = std::sqrt(placement.d2 * placement.d2 + placement.w2 * placement.w2 - wrist_radius * wrist_radius);
  tangent_angle_ = tangent_angle(placement, wrist_radius, centre);
  wrap_angle_at_zero_ = wrap_angle_at_zero(placement, wrist_radius, tangent_angle_);
  cos_q2_at_zero_ = std::cos(tangent_angle_ + wrap_angle_at_zero_);
  sin_q2_at_zero_ = std::sin(tangent_angle_ + wrap_angle_at_zero_);
}

MusclePath PlacementGeometry::at(const JointAngle& angle) const {
  const double joint_angle = angle.radians;
  require(std::isfinite(joint_angle) && std::abs(joint_angle) <= std::numbers::pi, "joint_angle [rad]", joint_angle,
          "must be finite and within [-pi, pi]");
  if (!centre_.at_joint()) return off_centre_at(angle);
  const double d2 = placement_.d2, w2 = placement_.w2;
  const double r_w = wrist_radius_;
  const double c = angle.cos;
  const double s = angle.sin;
  // Distances of centimetres: sqrt(x^2 + y^2) neither overflows nor underflows here, and std::hypot's care costs
  // more than the rest of the path (perf on `softwrist bench optimize`).
  const auto distance = [](double x, double y) { return std::sqrt(x * x + y * y); };

  const double psi = tangent_angle_;
  const double phi = wrap_angle_at_zero_ - joint_angle;  // Eqn. parameters2

  MusclePath path;
  path.wrap_angle = phi;
  path.tangent_angle = psi;
  const double p2x = d2 * c - w2 * s;
  const double p2y = d2 * s + w2 * c;
  if (phi > 0.0) {
    path.regime = Regime::kWrapping;
    // Eqn. length: the two tangents sqrt(R_i^2 - r_w^2) and the arc.
    path.length = tangent_length1_ + r_w * phi + tangent_length2_;
    // Eqn. tau2 with psi + phi (see header): cross product of O->P2 with the unit vector P2->Q2, times r_w. Q2's
    // polar angle psi + phi = (psi + phi0) - theta: its cosine and sine by the difference formulas, no trigonometry.
    const double cos_q2 = cos_q2_at_zero_ * c + sin_q2_at_zero_ * s;
    const double sin_q2 = sin_q2_at_zero_ * c - cos_q2_at_zero_ * s;
    const double p2q2 = distance(r_w * sin_q2 - p2x, r_w * cos_q2 - p2y);
    path.moment_arm = r_w / p2q2 * (p2x * cos_q2 - p2y * sin_q2);
  } else {
    set_straight(path, placement_, c, s, p2x, p2y);
  }
  return path;
}

// The same construction about C: Q1 fixed with the forearm, Q2 the tangent point from P2 (which turns about O), the
// wrapped arc between them on the muscle's side; the moment arm about O is O->P2 x the unit force direction at P2
// (towards Q2 when wrapped), which for C = O is Eqn. tau2; straight, the path is Eqn. tau1's whatever C.
MusclePath PlacementGeometry::off_centre_at(const JointAngle& angle) const {
  const double d2 = placement_.d2, w2 = placement_.w2;
  const double r_w = wrist_radius_;
  const double p2x = d2 * angle.cos - w2 * angle.sin, p2y = d2 * angle.sin + w2 * angle.cos;  // O->P2
  const double bx = p2x - centre_.x, by = p2y - centre_.y;                                    // C->P2
  const double r2 = std::sqrt(bx * bx + by * by);
  // C->P2's polar angle, continuous in theta: O->P2's, theta + atan2(w2, d2), turned by the angle from O->P2 to C->P2
  // (under pi/2: validate keeps |OC| below R2).
  const double polar_p2 = angle.radians + std::atan2(w2, d2) + std::atan2(p2x * by - p2y * bx, p2x * bx + p2y * by);
  const double q1_polar = std::numbers::pi / 2.0 - tangent_angle_;
  const double q2_polar = polar_p2 + std::acos(r_w / r2);

  MusclePath path;
  path.tangent_angle = tangent_angle_;
  path.wrap_angle = q1_polar - q2_polar;
  if (path.wrap_angle > 0.0) {
    path.regime = Regime::kWrapping;
    path.length = tangent_length1_ + r_w * path.wrap_angle + std::sqrt(r2 * r2 - r_w * r_w);
    const double ux = centre_.x + r_w * std::cos(q2_polar) - p2x, uy = centre_.y + r_w * std::sin(q2_polar) - p2y;
    path.moment_arm = (p2x * uy - p2y * ux) / std::sqrt(ux * ux + uy * uy);
  } else {
    set_straight(path, placement_, angle.cos, angle.sin, p2x, p2y);
  }
  return path;
}

MusclePath muscle_path(const Placement& placement, double wrist_radius, double joint_angle, WrapCentre centre) {
  return PlacementGeometry(placement, wrist_radius, centre).at(joint_angle);
}

}  // namespace softwrist::physics
