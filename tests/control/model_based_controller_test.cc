// The model-based controller (control/model_based_controller.h) without a simulation: its feedforward holds the
// analytic statics' equilibrium, its pressures stay in range, an out-of-reach target is reported and does not wind
// the integrator up, an invalid reading changes nothing.

#include "control/model_based_controller.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "physics/units.h"
#include "sim/device.h"
#include "sim/wrist_statics.h"

namespace softwrist::control {
namespace {

using physics::WristAxis;

ImuReading at(double fe_deg, double ur_deg, double t_s) {
  return {.angles = {.fe_deg = fe_deg, .ur_deg = ur_deg}, .time_s = t_s, .valid = true};
}

// Held at the desired angle with no error, the controller settles on pressures at which the analytic statics
// (physics/wrist_statics.h: muscles, relaxed wrist, hand weight) balance: the feedforward is the model's inverse.
TEST(ModelBasedController, FeedforwardBalancesTheAnalyticStatics) {
  const physics::WristModel wrist = sim::wrist_model(sim::rom_device());
  for (const WristAngles target : {WristAngles{-20.0, 5.0}, WristAngles{10.0, -8.0}, WristAngles{0.0, 0.0}}) {
    ModelBasedController controller(wrist);
    Pressures p{};
    for (int k = 0; k < 2000; ++k) {  // 28 s: the reference filter has long converged
      p = controller.command(k * 0.014, {.angles = target}, at(target.fe_deg, target.ur_deg, k * 0.014));
    }
    const double fe = units::deg_to_rad(target.fe_deg), ur = units::deg_to_rad(target.ur_deg);
    EXPECT_NEAR(
        physics::axis_torques(wrist, WristAxis::kFlexionExtension, fe, units::kpa_to_pa(p[0]), units::kpa_to_pa(p[1]))
            .net(),
        0.0, 1e-6);
    EXPECT_NEAR(
        physics::axis_torques(wrist, WristAxis::kUlnarRadial, ur, units::kpa_to_pa(p[2]), units::kpa_to_pa(p[3])).net(),
        0.0, 1e-6);
    EXPECT_FALSE(controller.unreachable()[0]);
    EXPECT_FALSE(controller.unreachable()[1]);
  }
}

// Random desired angles and readings, wildly out of range: every command stays within [0, max].
TEST(ModelBasedController, CommandsNeverLeaveTheRegulatorRange) {
  ModelBasedController controller(sim::wrist_model(sim::rom_device()));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-120.0, 120.0);
  for (int k = 0; k < 20000; ++k) {
    const double t = k * 0.014;
    for (double v : controller.command(t, {.angles = {angle(rng), angle(rng)}}, at(angle(rng), angle(rng), t))) {
      ASSERT_GE(v, 0.0);
      ASSERT_LE(v, 137.0);
    }
  }
}

// 70 deg of flexion is beyond what the exosuit can hold (physics::reachable_range): reported unreachable, the
// reference stops inside the range, and a minute of pushing at it leaves the controller in the same state as a
// second of it (the integral does not wind up), so that it comes back from it as fast.
TEST(ModelBasedController, OutOfReachTargetIsReportedWithoutWindUp) {
  const physics::WristModel wrist = sim::wrist_model(sim::rom_device());
  const auto push_then_return = [&](int push_ticks) {
    ModelBasedController controller(wrist);
    double t = 0.0;
    for (int k = 0; k < push_ticks; ++k, t += 0.014) {
      controller.command(t, {.angles = {70.0, 0.0}}, at(15.0, 0.0, t));  // the wrist stuck at 15 deg
      EXPECT_TRUE(controller.unreachable()[0]);
      EXPECT_FALSE(controller.unreachable()[1]);
    }
    Pressures p{};
    for (int k = 0; k < 100; ++k, t += 0.014) p = controller.command(t, {.angles = {0.0, 0.0}}, at(0.0, 0.0, t));
    EXPECT_FALSE(controller.unreachable()[0]);
    return p;
  };
  EXPECT_LT(units::rad_to_deg(ModelBasedController(wrist).reachable_range().flexion), 70.0);
  const Pressures after_minute = push_then_return(4286);
  const Pressures after_second = push_then_return(72);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(after_minute[i], after_second[i], 1.0) << i;
}

// An invalid or NaN reading holds the last pressures; bad parameters are refused.
TEST(ModelBasedController, InvalidReadingHoldsAndBadParametersAreRefused) {
  const physics::WristModel wrist = sim::wrist_model(sim::rom_device());
  ModelBasedController controller(wrist);
  const Pressures first = controller.command(0.0, {.angles = {10.0, 0.0}}, at(0.0, 0.0, 0.0));
  EXPECT_EQ(controller.command(0.014, {.angles = {30.0, 0.0}}, {}), first);
  EXPECT_EQ(controller.command(0.028, {.angles = {30.0, 0.0}}, at(NAN, 0.0, 0.02)), first);
  EXPECT_EQ(controller.command(0.042, {.angles = {NAN, 0.0}}, at(0.0, 0.0, 0.03)), first);
  EXPECT_THROW(ModelBasedController(wrist, {.period_s = 0.0}), std::invalid_argument);
  EXPECT_THROW(ModelBasedController(wrist, {.co_contraction_kpa = 200.0}), std::invalid_argument);
  EXPECT_THROW(ModelBasedController(wrist, {.kp_nm_per_rad = -1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace softwrist::control
