// Rise time, overshoot and RMSE (control/tracking_metrics.h) on signals whose figures are known by construction.

#include "control/tracking_metrics.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace softwrist::control {
namespace {

// A linear ramp from 0 to -10 deg over 1 s, then a hump 2 deg past the target decaying back to it: 10-90 % takes
// 0.8 s, the overshoot is 20 %, the final error 0.
TEST(StepResponse, RampWithAHumpHasKnownRiseTimeAndOvershoot) {
  std::vector<double> t, y;
  for (int i = 0; i <= 1000; ++i) {
    const double s = i * 0.01;
    t.push_back(s);
    const double ramp = s < 1.0 ? -10.0 * s : -10.0;
    const double hump = s > 1.0 && s < 3.0 ? -2.0 * std::sin(M_PI * (s - 1.0) / 2.0) : 0.0;
    y.push_back(ramp + hump);
  }
  const StepResponse r = step_response(t, y, 0.0, -10.0, {.smoothing_s = 0.0});
  EXPECT_NEAR(r.rise_time_s, 0.8, 0.011);
  EXPECT_NEAR(r.overshoot_pct, 20.0, 0.01);
  EXPECT_NEAR(r.final_error_deg, 0.0, 1e-12);
  // Never reaching 90 %: no rise time, and the shortfall shows in the final error.
  std::vector<double> short_of(y.size(), -5.0);
  const StepResponse s = step_response(t, short_of, 0.0, -10.0);
  EXPECT_TRUE(std::isnan(s.rise_time_s));
  EXPECT_NEAR(s.final_error_deg, 5.0, 1e-12);
  EXPECT_EQ(s.overshoot_pct, 0.0);
  EXPECT_THROW(step_response(t, {}, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(step_response(t, y, 1.0, 1.0), std::invalid_argument);
}

// Smoothing keeps white IMU-like noise from reading as overshoot on a perfect step.
TEST(StepResponse, SmoothingSuppressesAlternatingNoise) {
  std::vector<double> t, y;
  for (int i = 0; i < 700; ++i) {
    t.push_back(i * 0.014);
    y.push_back(10.0 + (i % 2 ? 0.3 : -0.3));
  }
  EXPECT_GT(step_response(t, y, 0.0, 10.0, {.smoothing_s = 0.0}).overshoot_pct, 2.9);
  EXPECT_LT(step_response(t, y, 0.0, 10.0).overshoot_pct, 1.1);
}

TEST(RmsError, IsTheRootMeanSquare) {
  EXPECT_DOUBLE_EQ(rms_error(std::vector<double>{0, 0, 0, 0}, std::vector<double>{1, -1, 1, -1}), 1.0);
  EXPECT_DOUBLE_EQ(rms_error(std::vector<double>{1, 2}, std::vector<double>{4, 6}), std::sqrt(12.5));
  EXPECT_TRUE(std::isnan(rms_error(std::vector<double>{}, std::vector<double>{})));
}

}  // namespace
}  // namespace softwrist::control
