#include "physics/torque_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <tuple>
#include <utility>

#include "physics/errors.h"
#include "physics/plausible_ranges.h"

namespace softwrist::physics {

const char* to_string(Regime regime) { return regime == Regime::kWrapping ? "wrapping" : "straight"; }

namespace {

// The surface's centre C nearer O than the hand mount, which turns about O: C -> P2 then stays within a right angle of
// O -> P2, and its polar angle follows the joint's continuously (PlacementGeometry::off_centre_at).
void require_centre_within_hand_mount(const Placement& placement, WrapSurface surface) {
  const double oc = std::hypot(surface.x, surface.y), r2 = std::hypot(placement.d2, placement.w2);
  require(oc < r2, "wrap centre distance |OC| [m]", oc,
          "must be less than the hand mount's distance R2 from the joint (the mount turns about O, around C)");
}

}  // namespace

void validate(const Placement& placement, double wrist_radius, WrapSurface surface) {
  require_positive("placement d1 [m]", placement.d1);
  require_non_negative("placement w1 [m]", placement.w1);
  require_positive("placement d2 [m]", placement.d2);
  require_non_negative("placement w2 [m]", placement.w2);
  require_positive("wrist_radius r_w [m]", wrist_radius);
  require_finite("wrap centre x [m]", surface.x);
  require_finite("wrap centre y [m]", surface.y);
  require(surface.aspect >= 0.25 && surface.aspect <= 4.0, "wrap surface aspect", surface.aspect,
          "must lie within [0.25, 4] (its semi-axis along the forearm over r_w)");
  for (const auto& [name, value] : {std::pair{"placement d1 [m]", placement.d1},
                                    {"placement w1 [m]", placement.w1},
                                    {"placement d2 [m]", placement.d2},
                                    {"placement w2 [m]", placement.w2},
                                    {"wrist_radius r_w [m]", wrist_radius},
                                    {"wrap centre x [m]", std::abs(surface.x)},
                                    {"wrap centre y [m]", std::abs(surface.y)}}) {
    require(value <= plausible::kMaxLength, name, value, "must be at most 10 (m; the arm is not that long)");
  }
  if (!surface.circular()) {
    // Scaled so that the ellipse is the unit circle, the forearm mount lies outside it, and so does the hand mount at
    // the joint's zero (where it comes closer as the wrist turns: hand_mount_clearance over the joint's range).
    const double a = surface.aspect * wrist_radius;
    const double u = std::hypot((placement.d1 + surface.x) / a, (placement.w1 - surface.y) / wrist_radius);
    require(u > 1.0, "forearm mount P1", u, "must lie outside the wrist's ellipse (its scaled distance above 1)");
    require_centre_within_hand_mount(placement, surface);
    const double v = hand_mount_clearance(placement, wrist_radius, surface, 0.0);
    require(v > 1.0, "hand mount P2", v,
            "must lie outside the wrist's ellipse at the joint's zero (its scaled distance above 1)");
    return;
  }
  const double r1 = std::hypot(placement.d1 + surface.x, placement.w1 - surface.y);  // |P1 - C|
  require(r1 > wrist_radius, "forearm mount distance R1 [m]", r1,
          "must exceed the wrist radius r_w (mount outside the wrist)");
  if (surface.at_joint()) {
    const double r2 = std::hypot(placement.d2, placement.w2);  // the same at every angle
    require(r2 > wrist_radius, "hand mount distance R2 [m]", r2,
            "must exceed the wrist radius r_w (mount outside the wrist)");
    return;
  }
  require_centre_within_hand_mount(placement, surface);
  const double v = hand_mount_clearance(placement, wrist_radius, surface, 0.0);
  require(v > 1.0, "hand mount distance |P2 - C| / r_w", v,
          "must exceed 1 at the joint's zero (mount outside the wrist circle)");
}

double hand_mount_clearance(const Placement& placement, double wrist_radius, WrapSurface surface, double max_angle) {
  const double a = surface.aspect * wrist_radius, b = wrist_radius;
  const double r2 = std::hypot(placement.d2, placement.w2), polar = std::atan2(placement.w2, placement.d2);
  const auto scaled_distance = [&](double theta) {
    return std::hypot((r2 * std::cos(polar + theta) - surface.x) / a, (r2 * std::sin(polar + theta) - surface.y) / b);
  };
  // Sampled at most every degree, then the least sample's neighbourhood refined by golden-section search (the
  // distance is smooth in theta and has at most two minima on the circle the mount turns on).
  require_finite("max_angle [rad]", max_angle);
  const double reach = std::min(std::abs(max_angle), std::numbers::pi);
  const int samples = std::max(1, static_cast<int>(std::ceil(2.0 * reach / (std::numbers::pi / 180.0))));
  double best = -reach, least = scaled_distance(-reach);
  for (int k = 1; k <= samples; ++k) {
    const double theta = -reach + 2.0 * reach * k / samples;
    if (const double d = scaled_distance(theta); d < least) std::tie(best, least) = std::pair(theta, d);
  }
  const double step = 2.0 * reach / samples;
  double lo = std::max(-reach, best - step), hi = std::min(reach, best + step);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int i = 0; i < 40 && hi - lo > 1e-9; ++i) {
    const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    if (scaled_distance(m1) < scaled_distance(m2)) {
      hi = m2;
    } else {
      lo = m1;
    }
  }
  return std::min(least, scaled_distance(0.5 * (lo + hi)));
}

namespace {

// psi of Eqn. parameters2. Q1 is the tangent point from P1 on the muscle's side: P1 lies at polar angle
// atan2(w1, -d1) about C, and the tangent from it touches the circle acos(r_w/R1) closer to +y; psi is measured from y.
double tangent_angle(const Placement& placement, double r_w, WrapSurface surface = {}) {
  const double x = -placement.d1 - surface.x, y = placement.w1 - surface.y;
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

// The wrapped path over an ellipse (C, semi-axes a along x and b along y), built where it is the unit circle: the
// tangent points Q1 from P1 and Q2 from P2 on the muscle's side, at parametric angles t1 and t2 (the point
// C + (a cos t, b sin t)); the muscle wraps when t1 > t2.
struct EllipticWrap {
  double p2x = 0.0, p2y = 0.0;  // the hand mount at the joint angle, O -> P2
  double t1 = 0.0, t2 = 0.0;
  double q1x = 0.0, q1y = 0.0, q2x = 0.0, q2y = 0.0;
  bool p2_inside = false;  // the hand mount within the ellipse (beyond the joint's reach): Q2 its foot (header)
};

// At joint angle theta, P2 = Rot(theta) (d2, w2).
EllipticWrap elliptic_wrap(const Placement& p, double a, double b, const WrapSurface& c, const JointAngle& theta) {
  EllipticWrap w;
  w.p2x = p.d2 * theta.cos - p.w2 * theta.sin;
  w.p2y = p.d2 * theta.sin + p.w2 * theta.cos;
  const double p2x = w.p2x, p2y = w.p2y;
  const double u1x = (-p.d1 - c.x) / a, u1y = (p.w1 - c.y) / b;
  const double u2x = (p2x - c.x) / a, u2y = (p2y - c.y) / b;
  // P1 lies behind the centre (x < 0): its polar angle taken in (0, 2 pi), continuous across the forearm's axis.
  double polar1 = std::atan2(u1y, u1x);
  if (polar1 < 0.0) polar1 += 2.0 * std::numbers::pi;
  w.t1 = polar1 - std::acos(1.0 / std::sqrt(u1x * u1x + u1y * u1y));
  const double n2 = std::sqrt(u2x * u2x + u2y * u2y);
  w.p2_inside = n2 <= 1.0;
  // P2's polar angle in the scaled coordinates about C, continuous in theta: within pi of O -> P2's own, theta +
  // atan2(w2, d2) (|OC| < R2 keeps C -> P2 within a right angle of O -> P2, and the scaling keeps each quadrant), not
  // atan2's cut, where a hand turned past about 106 deg jumped to a wrap of 246 deg.
  const double reference = theta.radians + std::atan2(p.w2, p.d2);
  double polar2 = std::atan2(u2y, u2x);
  polar2 += 2.0 * std::numbers::pi * std::round((reference - polar2) / (2.0 * std::numbers::pi));
  w.t2 = polar2 + (w.p2_inside ? 0.0 : std::acos(1.0 / n2));
  w.q1x = c.x + a * std::cos(w.t1);
  w.q1y = c.y + b * std::sin(w.t1);
  w.q2x = c.x + a * std::cos(w.t2);
  w.q2y = c.y + b * std::sin(w.t2);
  return w;
}

// The ellipse's arc length from parametric angle t0 to t1 > t0, integral of sqrt(a^2 sin^2 t + b^2 cos^2 t): 8-point
// Gauss-Legendre on panels of at most 0.5 rad (a smooth integrand: 1e-12 relative at aspects up to 4).
double ellipse_arc(double a, double b, double t0, double t1) {
  static constexpr std::array<double, 4> kNodes = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                                   0.9602898564975363};
  static constexpr std::array<double, 4> kWeights = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                                     0.1012285362903763};
  const int panels = std::max(1, static_cast<int>(std::ceil((t1 - t0) / 0.5)));
  const double h = (t1 - t0) / panels;
  double sum = 0.0;
  for (int k = 0; k < panels; ++k) {
    const double mid = t0 + (k + 0.5) * h;
    for (std::size_t i = 0; i < kNodes.size(); ++i) {
      for (const double side : {-1.0, 1.0}) {
        const double t = mid + side * 0.5 * h * kNodes[i];
        const double sx = a * std::sin(t), cy = b * std::cos(t);
        sum += kWeights[i] * 0.5 * h * std::sqrt(sx * sx + cy * cy);
      }
    }
  }
  return sum;
}

}  // namespace

double wrap_transition_angle(const Placement& placement, double wrist_radius) {
  validate(placement, wrist_radius);
  return wrap_angle_at_zero(placement, wrist_radius, tangent_angle(placement, wrist_radius));
}

PlacementGeometry::PlacementGeometry(const Placement& placement, double wrist_radius, WrapSurface surface)
    : placement_(placement), surface_(surface), wrist_radius_(wrist_radius) {
  validate(placement, wrist_radius, surface);
  if (!surface.circular()) return;                                            // elliptic_at builds the path per angle
  const double x1 = placement.d1 + surface.x, y1 = placement.w1 - surface.y;  // |P1 - C| = |(x1, y1)|
  tangent_length1_ = std::sqrt(x1 * x1 + y1 * y1 - wrist_radius * wrist_radius);
  tangent_length2_ = std::sqrt(placement.d2 * placement.d2 + placement.w2 * placement.w2 - wrist_radius * wrist_radius);
  tangent_angle_ = tangent_angle(placement, wrist_radius, surface);
  wrap_angle_at_zero_ = wrap_angle_at_zero(placement, wrist_radius, tangent_angle_);
  cos_q2_at_zero_ = std::cos(tangent_angle_ + wrap_angle_at_zero_);
  sin_q2_at_zero_ = std::sin(tangent_angle_ + wrap_angle_at_zero_);
}

MusclePath PlacementGeometry::at(const JointAngle& angle) const {
  const double joint_angle = angle.radians;
  require(std::isfinite(joint_angle) && std::abs(joint_angle) <= std::numbers::pi, "joint_angle [rad]", joint_angle,
          "must be finite and within [-pi, pi]");
  if (!surface_.circular()) return elliptic_at(angle);
  if (!surface_.at_joint()) return off_centre_at(angle);
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
  const double bx = p2x - surface_.x, by = p2y - surface_.y;                                  // C->P2
  const double r2 = std::sqrt(bx * bx + by * by);
  // C->P2's polar angle, continuous in theta: O->P2's, theta + atan2(w2, d2), turned by the angle from O->P2 to C->P2
  // (under pi/2: validate keeps |OC| below R2).
  const double polar_p2 = angle.radians + std::atan2(w2, d2) + std::atan2(p2x * by - p2y * bx, p2x * bx + p2y * by);
  const double q1_polar = std::numbers::pi / 2.0 - tangent_angle_;
  // A mount inside the circle (beyond the joint's reach, hand_mount_clearance): the path continued through its foot
  // on the circle (header), Q2 at the mount's own polar angle.
  const bool inside = r2 <= r_w;
  const double q2_polar = polar_p2 + (inside ? 0.0 : std::acos(r_w / r2));

  MusclePath path;
  path.tangent_angle = tangent_angle_;
  path.wrap_angle = q1_polar - q2_polar;
  if (path.wrap_angle > 0.0) {
    path.regime = Regime::kWrapping;
    path.length = tangent_length1_ + r_w * path.wrap_angle + (inside ? r_w - r2 : std::sqrt(r2 * r2 - r_w * r_w));
    // Towards Q2; inside, along the circle at the foot (the limit of P2 -> Q2 as the mount reaches the circle).
    const double ux = inside ? -std::sin(q2_polar) : surface_.x + r_w * std::cos(q2_polar) - p2x;
    const double uy = inside ? std::cos(q2_polar) : surface_.y + r_w * std::sin(q2_polar) - p2y;
    path.moment_arm = (p2x * uy - p2y * ux) / std::sqrt(ux * ux + uy * uy);
  } else {
    set_straight(path, placement_, angle.cos, angle.sin, p2x, p2y);
  }
  return path;
}

// The off-centre construction on an ellipse (elliptic_wrap): the arc by quadrature, the moment arm about O from the
// force direction at P2, towards Q2.
MusclePath PlacementGeometry::elliptic_at(const JointAngle& angle) const {
  const double a = surface_.aspect * wrist_radius_, b = wrist_radius_;
  const EllipticWrap w = elliptic_wrap(placement_, a, b, surface_, angle);
  const double p2x = w.p2x, p2y = w.p2y;
  MusclePath path;
  path.tangent_angle = std::atan2(w.q1x - surface_.x, w.q1y - surface_.y);  // from y to C->Q1, towards x
  path.wrap_angle = w.t1 - w.t2;
  if (path.wrap_angle <= 0.0) {
    set_straight(path, placement_, angle.cos, angle.sin, p2x, p2y);
    return path;
  }
  path.regime = Regime::kWrapping;
  const double ux = w.q2x - p2x, uy = w.q2y - p2y;  // P2 -> Q2
  const double tail = std::sqrt(ux * ux + uy * uy);
  path.length = std::hypot(w.q1x + placement_.d1, w.q1y - placement_.w1) + ellipse_arc(a, b, w.t2, w.t1) + tail;
  if (w.p2_inside) {
    // Along the ellipse at the foot, towards larger t: the limit of P2 -> Q2 as the mount reaches the ellipse.
    const double tx = -a * std::sin(w.t2), ty = b * std::cos(w.t2);
    path.moment_arm = (p2x * ty - p2y * tx) / std::sqrt(tx * tx + ty * ty);
  } else {
    path.moment_arm = (p2x * uy - p2y * ux) / tail;
  }
  return path;
}

MusclePath muscle_path(const Placement& placement, double wrist_radius, double joint_angle, WrapSurface surface) {
  return PlacementGeometry(placement, wrist_radius, surface).at(joint_angle);
}

TangentPoints tangent_points(const Placement& placement, double wrist_radius, WrapSurface surface, double joint_angle,
                             const MusclePath& path) {
  if (!surface.circular()) {
    const EllipticWrap w =
        elliptic_wrap(placement, surface.aspect * wrist_radius, wrist_radius, surface, JointAngle(joint_angle));
    return {w.q1x, w.q1y, w.q2x, w.q2y};
  }
  const double psi = path.tangent_angle, phi = path.wrap_angle;
  return {surface.x + wrist_radius * std::sin(psi), surface.y + wrist_radius * std::cos(psi),
          surface.x + wrist_radius * std::sin(psi + phi), surface.y + wrist_radius * std::cos(psi + phi)};
}

EquivalentCircle equivalent_circle(const Placement& placement, double wrist_radius, WrapSurface surface,
                                   double joint_angle, const MusclePath& path) {
  const double a = surface.aspect * wrist_radius, b = wrist_radius;
  if (path.regime != Regime::kWrapping) return {surface.x, surface.y, std::min(a, b)};
  if (surface.circular()) return {surface.x, surface.y, wrist_radius};
  const double p1x = -placement.d1, p1y = placement.w1;
  const EllipticWrap w = elliptic_wrap(placement, a, b, surface, JointAngle(joint_angle));
  const double p2x = w.p2x, p2y = w.p2y;
  // Beyond the joint's reach, the hand mount inside the ellipse (validate): no circle stands in for the continued path;
  // the inscribed one, as for a straight path, keeps MuJoCo's wrap defined (so does a radius the formula cannot give,
  // below).
  const EquivalentCircle inscribed{surface.x, surface.y, std::min(a, b)};
  if (w.p2_inside) return inscribed;
  // Unit directions of the two segments, P1 -> Q1 and Q2 -> P2, and the turn between them (the path bends clockwise
  // over the muscle's side: the cross product is negative).
  double e1x = w.q1x - p1x, e1y = w.q1y - p1y, e2x = p2x - w.q2x, e2y = p2y - w.q2y;
  const double n1 = std::hypot(e1x, e1y), n2 = std::hypot(e2x, e2y);
  e1x /= n1, e1y /= n1, e2x /= n2, e2y /= n2;
  const double turn = std::abs(std::atan2(e1x * e2y - e1y * e2x, e1x * e2x + e1y * e2y));
  // The inside of the bend, where the centre lies: along e2 - e1.
  const double bx = e2x - e1x, by = e2y - e1y, nb = std::hypot(bx, by);
  if (turn < 0.02) {
    const double mid = 0.5 * (w.t1 + w.t2), sx = a * std::sin(mid), cy = b * std::cos(mid);
    const double curvature_radius = std::pow(sx * sx + cy * cy, 1.5) / (a * b);
    const double mx = surface.x + a * std::cos(mid), my = surface.y + b * std::sin(mid);  // the arc's middle
    return {mx + bx / nb * curvature_radius, my + by / nb * curvature_radius, curvature_radius};
  }
  // X: where the lines P1 + u e1 and P2 - v e2 meet.
  const double cross = e1x * e2y - e1y * e2x;
  const double u = ((p2x - p1x) * e2y - (p2y - p1y) * e2x) / cross;
  const double xx = p1x + u * e1x, xy = p1y + u * e1y;
  const double through_x = std::hypot(xx - p1x, xy - p1y) + std::hypot(p2x - xx, p2y - xy);
  const double radius = (through_x - path.length) / (2.0 * std::tan(0.5 * turn) - turn);
  if (!(radius > 0.0 && radius < plausible::kMaxLength)) return inscribed;
  const double to_centre = radius / std::cos(0.5 * turn);
  return {xx + bx / nb * to_centre, xy + by / nb * to_centre, radius};
}

}  // namespace softwrist::physics
