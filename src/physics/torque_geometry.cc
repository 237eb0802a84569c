#include "physics/torque_geometry.h"

#include <cmath>
#include <numbers>

#include "physics/errors.h"
#include "physics/plausible_ranges.h"

namespace softwrist::physics {

const char* to_string(Regime regime) { return regime == Regime::kWrapping ? "wrapping" : "straight"; }

void validate(const Placement& placement, double wrist_radius) {
  require_positive("placement d1 [m]", placement.d1);
  require_non_negative("placement w1 [m]", placement.w1);
  require_positive("placement d2 [m]", placement.d2);
  require_non_negative("placement w2 [m]", placement.w2);
  require_positive("wrist_radius r_w [m]", wrist_radius);
  for (const auto& [name, value] : {std::pair{"placement d1 [m]", placement.d1},
                                    {"placement w1 [m]", placement.w1},
                                    {"placement d2 [m]", placement.d2},
                                    {"placement w2 [m]", placement.w2},
                                    {"wrist_radius r_w [m]", wrist_radius}}) {
    require(value <= plausible::kMaxLength, name, value, "must be at most 10 (m; the arm is not that long)");
  }
  require(std::hypot(placement.d1, placement.w1) > wrist_radius, "forearm mount distance R1 [m]",
          std::hypot(placement.d1, placement.w1), "must exceed the wrist radius r_w (mount outside the wrist)");
  require(std::hypot(placement.d2, placement.w2) > wrist_radius, "hand mount distance R2 [m]",
          std::hypot(placement.d2, placement.w2), "must exceed the wrist radius r_w (mount outside the wrist)");
}

namespace {

// psi of Eqn. parameters2. Q1 is the tangent point from P1 on the muscle's side: P1 lies at polar angle
// atan2(w1, -d1), and the tangent from it touches the circle acos(r_w/R1) closer to +y; psi is measured from y.
double tangent_angle(const Placement& placement, double r_w) {
  const double q1_polar =
      std::atan2(placement.w1, -placement.d1) - std::acos(r_w / std::hypot(placement.d1, placement.w1));
  return std::numbers::pi / 2.0 - q1_polar;
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

PlacementGeometry::PlacementGeometry(const Placement& placement, double wrist_radius)
    : placement_(placement), wrist_radius_(wrist_radius) {
  validate(placement, wrist_radius);
  tangent_length1_ = std::sqrt(placement.d1 * placement.d1 + placement.w1 * placement.w1 - wrist_radius * wrist_radius);
  tangent_length2_ = std::sqrt(placement.d2 * placement.d2 + placement.w2 * placement.w2 - wrist_radius * wrist_radius);
  tangent_angle_ = tangent_angle(placement, wrist_radius);
  wrap_angle_at_zero_ = wrap_angle_at_zero(placement, wrist_radius, tangent_angle_);
  cos_q2_at_zero_ = std::cos(tangent_angle_ + wrap_angle_at_zero_);
  sin_q2_at_zero_ = std::sin(tangent_angle_ + wrap_angle_at_zero_);
}

MusclePath PlacementGeometry::at(const JointAngle& angle) const {
  const double joint_angle = angle.radians;
  require(std::isfinite(joint_angle) && std::abs(joint_angle) <= std::numbers::pi, "joint_angle [rad]", joint_angle,
          "must be finite and within [-pi, pi]");
  const auto [d1, w1, d2, w2] = placement_;
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
    path.regime = Regime::kStraight;
    // Eqn. tau1.
    path.length = distance(-d1 - p2x, w1 - p2y);
    path.moment_arm = ((d1 * d2 - w1 * w2) * s + (d1 * w2 + d2 * w1) * c) / path.length;
  }
  return path;
}

MusclePath muscle_path(const Placement& placement, double wrist_radius, double joint_angle) {
  return PlacementGeometry(placement, wrist_radius).at(joint_angle);
}

}  // namespace softwrist::physics
