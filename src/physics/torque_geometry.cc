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

MusclePath muscle_path(const Placement& placement, double wrist_radius, double joint_angle) {
  validate(placement, wrist_radius);
  require(std::isfinite(joint_angle) && std::abs(joint_angle) <= std::numbers::pi, "joint_angle [rad]", joint_angle,
          "must be finite and within [-pi, pi]");
  const auto [d1, w1, d2, w2] = placement;
  const double r_w = wrist_radius;
  const double c = std::cos(joint_angle);
  const double s = std::sin(joint_angle);
  const double r1 = std::hypot(d1, w1);
  const double r2 = std::hypot(d2, w2);

  const double psi = tangent_angle(placement, r_w);
  const double phi = wrap_angle_at_zero(placement, r_w, psi) - joint_angle;  // Eqn. parameters2

  MusclePath path;
  path.wrap_angle = phi;
  path.tangent_angle = psi;
  const double p2x = d2 * c - w2 * s;
  const double p2y = d2 * s + w2 * c;
  if (phi > 0.0) {
    path.regime = Regime::kWrapping;
    // Eqn. length.
    path.length = std::sqrt(r1 * r1 - r_w * r_w) + r_w * phi + std::sqrt(r2 * r2 - r_w * r_w);
    // Eqn. tau2 with psi + phi (see header): cross product of O->P2 with the unit vector P2->Q2, times r_w.
    const double q2_angle = psi + phi;
    const double p2q2 = std::hypot(r_w * std::sin(q2_angle) - p2x, r_w * std::cos(q2_angle) - p2y);
    path.moment_arm = r_w / p2q2 * (p2x * std::cos(q2_angle) - p2y * std::sin(q2_angle));
  } else {
    path.regime = Regime::kStraight;
    // Eqn. tau1.
    path.length = std::hypot(-d1 - p2x, w1 - p2y);
    path.moment_arm = ((d1 * d2 - w1 * w2) * s + (d1 * w2 + d2 * w1) * c) / path.length;
  }
  return path;
}

}  // namespace softwrist::physics
