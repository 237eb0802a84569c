// MATLAB's spline(): not-a-knot cubic (Section Parameter optimization resamples the reference with it).

#include "optimize/cubic_spline.h"

#include <cmath>

#include <gtest/gtest.h>

namespace softwrist::optimize {
namespace {

// Not-a-knot end conditions make the spline exact for any cubic: MATLAB's spline(x, p(x)) returns p.
TEST(CubicSpline, NotAKnotReproducesACubicExactly) {
  const auto p = [](double x) { return 0.5 * x * x * x - 2.0 * x * x + x - 3.0; };
  std::vector<double> x = {-2.0, -1.2, 0.0, 0.7, 2.5, 3.0, 4.1, 5.0}, y;
  for (double xi : x) y.push_back(p(xi));
  const CubicSpline spline(x, y);
  for (double t = -2.5; t <= 5.5; t += 0.05) EXPECT_NEAR(spline(t), p(t), 1e-9) << t;
}

TEST(CubicSpline, ThreePointsGiveTheParabolaAndTwoTheLine) {
  const CubicSpline parabola({0.0, 1.0, 3.0}, {1.0, 2.0, 10.0});  // y = x^2 + 1
  EXPECT_NEAR(parabola(2.0), 5.0, 1e-12);
  const CubicSpline line({0.0, 2.0}, {1.0, 5.0});
  EXPECT_NEAR(line(1.5), 4.0, 1e-12);
}

TEST(CubicSpline, RejectsUnsortedOrNonFinitePoints) {
  EXPECT_THROW(CubicSpline({0.0, 0.0, 1.0}, {1.0, 2.0, 3.0}), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, 1.0}, {1.0, NAN}), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0}, {1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace softwrist::optimize
