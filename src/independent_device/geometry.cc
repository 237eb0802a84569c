#include "independent_device/geometry.h"

#include <array>
#include <cmath>

#include "independent_device/units.h"

namespace softwrist::independent {
namespace {

struct Vec {
  double x = 0.0, y = 0.0;
};
double norm(Vec v) { return std::hypot(v.x, v.y); }

// Arc length of the ellipse (a cos t, b sin t) for t in [t0, t1]: composite 5-point Gauss-Legendre on 4 panels
// (smooth periodic integrand; relative error far below 1e-8 for the axis ratios used here).
double ellipse_arc(double a, double b, double t0, double t1) {
  static constexpr std::array<double, 5> kNodes{0.0, 0.5384693101056831, -0.5384693101056831, 0.9061798459386640,
                                                -0.9061798459386640};
  static constexpr std::array<double, 5> kWeights{0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                                  0.2369268850561891, 0.2369268850561891};
  constexpr int kPanels = 4;
  const double h = (t1 - t0) / kPanels;
  double sum = 0.0;
  for (int p = 0; p < kPanels; ++p) {
    const double mid = t0 + (p + 0.5) * h;
    for (std::size_t i = 0; i < kNodes.size(); ++i) {
      const double t = mid + 0.5 * h * kNodes[i];
      sum += kWeights[i] * std::hypot(a * std::sin(t), b * std::cos(t));
    }
  }
  return 0.5 * h * sum;
}

}  // namespace

Path muscle_path(const Placement& placement, const WrapSurface& wrap, double theta_rad, double hand_slide_m) {
  const double c = std::cos(theta_rad), s = std::sin(theta_rad);
  const double hx = placement.d2_m - hand_slide_m, hy = placement.w2_m;
  const Vec p1{-placement.d1_m, placement.w1_m};
  const Vec p2{hx * c - hy * s, hx * s + hy * c};

  Path straight;
  const Vec to_p1{p1.x - p2.x, p1.y - p2.y};
  straight.length_m = norm(to_p1);
  straight.moment_arm_m = (p2.x * to_p1.y - p2.y * to_p1.x) / straight.length_m;

  const double a = wrap.semi_x_m, b = wrap.semi_y_m;
  if (a <= 0.0 || b <= 0.0) return straight;
  const Vec q1{(p1.x - wrap.centre_x_m) / a, (p1.y - wrap.centre_y_m) / b};
  const Vec q2{(p2.x - wrap.centre_x_m) / a, (p2.y - wrap.centre_y_m) / b};
  const double n1 = norm(q1), n2 = norm(q2);
  if (n1 <= 1.0 || n2 <= 1.0) return straight;  // an anchor inside the surface: wrapping undefined
  // On the muscle's side the string runs clockwise (decreasing polar angle) from P1 over the surface to P2.
  const double t1 = std::atan2(q1.y, q1.x) - std::acos(1.0 / n1);
  const double t2 = std::atan2(q2.y, q2.x) + std::acos(1.0 / n2);
  const double phi = std::remainder(t1 - t2, 2.0 * kPi);
  if (phi <= 0.0) return straight;

  const Vec k1{wrap.centre_x_m + a * std::cos(t1), wrap.centre_y_m + b * std::sin(t1)};
  const Vec k2{wrap.centre_x_m + a * std::cos(t2), wrap.centre_y_m + b * std::sin(t2)};
  const double arc = (a == b) ? a * phi : ellipse_arc(a, b, t2, t2 + phi);
  const Vec to_k2{k2.x - p2.x, k2.y - p2.y};
  const double free2 = norm(to_k2);
  Path wrapped;
  wrapped.length_m = norm(Vec{p1.x - k1.x, p1.y - k1.y}) + arc + free2;
  wrapped.moment_arm_m = (p2.x * to_k2.y - p2.y * to_k2.x) / free2;
  wrapped.wrapped = true;
  return wrapped;
}

}  // namespace softwrist::independent
