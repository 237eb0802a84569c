#pragma once
// The interpolating cubic spline MATLAB's spline() computes (Section Parameter optimization resamples the
// reference torque with it): not-a-knot end conditions for four or more points, the interpolating parabola for
// three, the line for two.

#include <vector>

namespace softwrist::optimize {

class CubicSpline {
 public:
  // x strictly increasing, x.size() == y.size() >= 2, all finite; std::invalid_argument otherwise.
  CubicSpline(std::vector<double> x, std::vector<double> y);
  // The spline at x; outside [x.front(), x.back()] the end polynomials are extended (as MATLAB does).
  double operator()(double x) const;

 private:
  std::vector<double> x_, y_;
  std::vector<double> second_derivative_;  // M_i at each knot
};

}  // namespace softwrist::optimize
