// The regulator's response (physics/pressure_regulator.h): the first-order lag at tau2 = 0, the second-order step
// response of tau2^2 p'' + tau p' + p = u in its closed forms, stable steps however fast the second pole.
#include "physics/pressure_regulator.h"

#include <cmath>

#include <gtest/gtest.h>

namespace softwrist::physics {
namespace {

constexpr double kDt = 1e-3;  // MuJoCo's step in softwrist's models

// The response to a step of the command from rest, stepped in kDt.
double pressure_after(const RegulatorResponse& response, double command, double duration) {
  RegulatedPressure state;
  for (int k = 0; k < static_cast<int>(std::lround(duration / kDt)); ++k)
    state = regulator_step(response, state, command, kDt);
  return state.pressure;
}

// The second-order system's unit step response from rest (Ogata, Modern Control Engineering, 5th ed., Sec. 5-3).
double unit_step(double tau, double tau2, double t) {
  const double wn = 1.0 / tau2, zeta = tau / (2.0 * tau2);
  if (zeta < 1.0) {
    const double wd = wn * std::sqrt(1.0 - zeta * zeta);
    return 1.0 - std::exp(-zeta * wn * t) * (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t));
  }
  if (zeta == 1.0) return 1.0 - std::exp(-wn * t) * (1.0 + wn * t);
  const double root = std::sqrt(zeta * zeta - 1.0);
  const double s1 = -wn * (zeta - root), s2 = -wn * (zeta + root);
  return 1.0 + (s2 * std::exp(s1 * t) - s1 * std::exp(s2 * t)) / (s1 - s2);
}

// At its neutral tau2 = 0 the regulator is the first-order lag exactly (issue 19: each extension reduces to the
// paper's default), in steps and in rate.
TEST(PressureRegulator, WithoutASecondTimeIsTheFirstOrderLag) {
  const RegulatorResponse first{.time_constant = 0.1};
  EXPECT_FALSE(first.second_order());
  for (const double t : {0.01, 0.05, 0.1, 0.3}) {
    EXPECT_NEAR(pressure_after(first, 100.0, t), 100.0 * (1.0 - std::exp(-t / 0.1)), 1e-9) << t;
  }
  EXPECT_DOUBLE_EQ(pressure_rate(first, 100.0, 20.0), 800.0);
  const RegulatedPressure next = regulator_step(first, {20.0, 0.0}, 100.0, kDt);
  EXPECT_NEAR(next.rate, pressure_rate(first, 100.0, next.pressure), 1e-9);
}

TEST(PressureRegulator, SecondOrderStepResponseIsTheClosedForm) {
  for (const double tau2 : {0.02, 0.05, 0.08, 0.2}) {  // damping ratios 2.5, 1, 0.625, 0.25
    const RegulatorResponse response{.time_constant = 0.1, .second_order_time = tau2};
    for (const double t : {0.01, 0.03, 0.1, 0.25, 0.6}) {
      EXPECT_NEAR(pressure_after(response, 100.0, t), 100.0 * unit_step(0.1, tau2, t), 1e-7)
          << "tau2 " << tau2 << " t " << t;
    }
  }
  // Underdamped (tau2 > tau/2): it overshoots, by exp(-pi zeta / sqrt(1 - zeta^2)) of the step.
  const RegulatorResponse ringing{.time_constant = 0.1, .second_order_time = 0.2};
  double peak = 0.0;
  for (double t = 0.0; t < 2.0; t += 0.01) peak = std::max(peak, pressure_after(ringing, 100.0, t));
  EXPECT_NEAR(peak, 100.0 * (1.0 + std::exp(-M_PI * 0.25 / std::sqrt(1.0 - 0.0625))), 0.2);
}

// A small tau2 only delays the start of the rise: the response approaches the first-order lag continuously.
TEST(PressureRegulator, ASmallSecondTimeApproachesTheFirstOrderLag) {
  const RegulatorResponse first{.time_constant = 0.1};
  double previous = INFINITY;
  for (const double tau2 : {0.02, 0.01, 0.003}) {
    const RegulatorResponse response{.time_constant = 0.1, .second_order_time = tau2};
    double largest = 0.0;
    for (const double t : {0.005, 0.02, 0.05, 0.1, 0.3})
      largest = std::max(largest, std::abs(pressure_after(response, 100.0, t) - pressure_after(first, 100.0, t)));
    EXPECT_LT(largest, previous) << tau2;
    previous = largest;
  }
  EXPECT_LT(previous, 1.0);  // kPa of a 100 kPa step
}

// The step is exact, so a second pole far beyond the step's rate (tau/tau2^2 = 1e8 1/s against 1 ms) stays stable.
TEST(PressureRegulator, StiffSecondPoleStaysStable) {
  const RegulatorResponse stiff{.time_constant = 1.0, .second_order_time = 1e-4};
  RegulatedPressure state;
  for (int k = 0; k < 5000; ++k) {
    state = regulator_step(stiff, state, 100.0, kDt);
    ASSERT_TRUE(std::isfinite(state.pressure) && std::isfinite(state.rate)) << k;
    ASSERT_LE(state.pressure, 100.0 + 1e-9) << k;  // overdamped: never beyond the command
  }
  EXPECT_NEAR(state.pressure, 100.0 * (1.0 - std::exp(-5.0)), 0.01);
}

// While the command lies below the pressure the venting time constant sets the damping.
TEST(PressureRegulator, VentsWithItsOwnTimeConstant) {
  const RegulatorResponse response{.time_constant = 0.05, .vent_time_constant = 0.2, .second_order_time = 0.02};
  RegulatedPressure state{100.0, 0.0};
  for (int k = 0; k < 100; ++k) state = regulator_step(response, state, 0.0, kDt);
  EXPECT_NEAR(state.pressure, 100.0 * (1.0 - unit_step(0.2, 0.02, 0.1)), 1e-7);
  const RegulatorResponse first{.time_constant = 0.05, .vent_time_constant = 0.2};
  EXPECT_DOUBLE_EQ(pressure_rate(first, 20.0, 100.0), -400.0);
}

}  // namespace
}  // namespace softwrist::physics
