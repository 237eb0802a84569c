#include "optimize/cubic_spline.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

namespace softwrist::optimize {

CubicSpline::CubicSpline(std::vector<double> x, std::vector<double> y) : x_(std::move(x)), y_(std::move(y)) {
  const std::size_t n = x_.size();
  if (n < 2 || y_.size() != n) throw std::invalid_argument("spline: needs at least two points, as many x as y");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x_[i]) || !std::isfinite(y_[i])) throw std::invalid_argument("spline: non-finite point");
    if (i > 0 && !(x_[i] > x_[i - 1])) throw std::invalid_argument("spline: x must be strictly increasing");
  }
  second_derivative_.assign(n, 0.0);
  if (n == 2) return;  // the line

  // Unknowns M_0..M_{n-1} (second derivatives). Interior rows: C2 continuity,
  // h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (s_i - s_{i-1}), s_i the secant slopes.
  // End rows: not-a-knot (the third derivative is continuous at x_1 and x_{n-2}); with three points both end
  // rows say the same, so the spline is the parabola through them (M constant).
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  std::vector<double> h(n - 1), slope(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = x_[i + 1] - x_[i];
    slope[i] = (y_[i + 1] - y_[i]) / h[i];
  }
  for (std::size_t i = 1; i + 1 < n; ++i) {
    a(i, i - 1) = h[i - 1];
    a(i, i) = 2.0 * (h[i - 1] + h[i]);
    a(i, i + 1) = h[i];
    b(i) = 6.0 * (slope[i] - slope[i - 1]);
  }
  if (n == 3) {
    a(0, 0) = 1.0, a(0, 1) = -1.0;
    a(2, 1) = 1.0, a(2, 2) = -1.0;
  } else {
    // (M_1 - M_0)/h_0 = (M_2 - M_1)/h_1, and the same at the far end.
    a(0, 0) = h[1], a(0, 1) = -(h[0] + h[1]), a(0, 2) = h[0];
    a(n - 1, n - 3) = h[n - 2], a(n - 1, n - 2) = -(h[n - 3] + h[n - 2]), a(n - 1, n - 1) = h[n - 3];
  }
  const Eigen::VectorXd m = a.fullPivLu().solve(b);
  for (std::size_t i = 0; i < n; ++i) second_derivative_[i] = m(i);
}

double CubicSpline::operator()(double x) const {
  // The interval [x_i, x_{i+1}] holding x (the first or last one outside the knots).
  const auto upper = std::upper_bound(x_.begin() + 1, x_.end() - 1, x);
  const std::size_t i = static_cast<std::size_t>(upper - x_.begin()) - 1;
  const double h = x_[i + 1] - x_[i];
  const double t = x - x_[i];
  const double m0 = second_derivative_[i], m1 = second_derivative_[i + 1];
  const double slope = (y_[i + 1] - y_[i]) / h - h * (2.0 * m0 + m1) / 6.0;
  return y_[i] + t * (slope + t * (m0 / 2.0 + t * (m1 - m0) / (6.0 * h)));
}

}  // namespace softwrist::optimize
