// The tracking loop (control/tracking_loop.h) on a scripted plant: zeroing, inactive pairs vented, commands kept in
// the regulator range whatever the controller says, the reachability watch, venting at the end.

#include "control/tracking_loop.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace softwrist::control {
namespace {

// A plant whose IMUs read a fixed offset plus a flexion angle that follows the flexor-extensor pressure
// difference (0.1 deg per kPa), and which records every command.
class ScriptedPlant final : public Plant {
 public:
  void command_pressures_kpa(const Pressures& p) override { commands.push_back(p); }
  ImuReading read_angles() override {
    const Pressures last = commands.empty() ? Pressures{} : commands.back();
    return {.angles = {.fe_deg = offset_fe + 0.1 * (last[0] - last[1]), .ur_deg = offset_ur},
            .time_s = time_,
            .valid = true};
  }
  double time_s() const override { return time_; }
  void wait_until(double t) override { time_ = t; }
  double max_pressure_kpa() const override { return 100.0; }
  std::vector<Pressures> commands;
  double offset_fe = 3.0, offset_ur = -2.0;

 private:
  double time_ = 5.0;  // a run need not start at zero
};

// Commands a fixed set of pressures and remembers what it was shown.
class FixedController final : public Controller {
 public:
  explicit FixedController(Pressures p) : pressures_(p) {}
  std::string name() const override { return "fixed"; }
  double period_s() const override { return 0.1; }
  void reset() override { seen.clear(); }
  Pressures command(double, const Reference&, const ImuReading& reading) override {
    seen.push_back(reading);
    return pressures_;
  }
  std::vector<ImuReading> seen;

 private:
  Pressures pressures_;
};

// The IMU offset at the start is removed (the paper zeroes the angles at the neutral wrist); the run takes
// duration / period iterations on the plant's clock; out-of-range and NaN commands reach the plant clamped; the
// inactive ulnar/radial pair is vented; the plant is vented at the end.
TEST(TrackingLoop, ZeroesClampsVentsAndCountsIterations) {
  ScriptedPlant plant;
  FixedController controller({250.0, NAN, 40.0, -3.0});
  const StepTrajectory hold({{0.0, 0.0}}, 2.0);
  std::vector<TrackingSample> samples;
  const long ticks = run_tracking(plant, controller, hold, {.active_axes = {true, false}},
                                  [&](const TrackingSample& s) { samples.push_back(s); });
  EXPECT_EQ(ticks, 20);
  ASSERT_EQ(samples.size(), 20u);
  EXPECT_NEAR(controller.seen.front().angles.fe_deg, 0.0, 1e-12);
  EXPECT_NEAR(controller.seen.front().angles.ur_deg, 0.0, 1e-12);
  EXPECT_NEAR(controller.seen.front().time_s, 0.0, 1e-12);
  EXPECT_NEAR(samples.back().t_s, 1.9, 1e-12);
  // After the first command the flexor (clamped to 100) moves the scripted angle by 10 deg; the offset stays removed.
  EXPECT_NEAR(controller.seen[1].angles.fe_deg, 10.0, 1e-12);
  EXPECT_NEAR(controller.seen[1].angles.ur_deg, 0.0, 1e-12);
  for (std::size_t i = 0; i + 1 < plant.commands.size(); ++i) {
    EXPECT_EQ(plant.commands[i], (Pressures{100.0, 0.0, 0.0, 0.0}));
  }
  EXPECT_EQ(plant.commands.back(), (Pressures{0.0, 0.0, 0.0, 0.0}));
}

// On hardware (OutOfRange::kStop) a command outside the regulator range is a controller fault: the plant is vented
// and the run stops with the muscle and the value named; nothing out of range reaches the plant.
TEST(TrackingLoop, StopsAndVentsOnAnOutOfRangeCommandWhenAskedTo) {
  for (const Pressures& bad :
       {Pressures{250.0, 0.0, 0.0, 0.0}, Pressures{0.0, NAN, 0.0, 0.0}, Pressures{0.0, 0.0, 0.0, -3.0}}) {
    ScriptedPlant plant;
    FixedController controller(bad);
    const StepTrajectory hold({{0.0, 0.0}}, 2.0);
    TrackingOptions options;
    options.out_of_range = TrackingOptions::OutOfRange::kStop;
    EXPECT_THROW(run_tracking(plant, controller, hold, options, nullptr), ControllerFault);
    ASSERT_EQ(plant.commands.size(), 1u);
    EXPECT_EQ(plant.commands.back(), (Pressures{0.0, 0.0, 0.0, 0.0}));
  }
  ScriptedPlant plant;
  FixedController controller({250.0, 0.0, 0.0, 0.0});
  TrackingOptions options;
  options.out_of_range = TrackingOptions::OutOfRange::kStop;
  try {
    run_tracking(plant, controller, StepTrajectory({{0.0, 0.0}}, 1.0), options, nullptr);
    FAIL() << "no fault";
  } catch (const ControllerFault& e) {
    EXPECT_STREQ(e.what(),
                 "controller 'fixed' asked for 250 kPa on the flexor at t = 0.000 s, outside the "
                 "regulators' 0-100 kPa: vented and stopped");
  }
}

// A target the controller pushes at with the agonist at the regulator's maximum, without getting there, is flagged
// after the dwell time, and only then.
TEST(TrackingLoop, FlagsATargetPushedAtFullPressureWithoutGettingThere) {
  ScriptedPlant plant;
  FixedController controller({100.0, 0.0, 0.0, 0.0});  // the scripted angle settles at 10 deg
  const StepTrajectory far({{60.0, 0.0}}, 3.0);
  std::vector<TrackingSample> samples;
  run_tracking(plant, controller, far, {.unreachable_dwell_s = 1.0},
               [&](const TrackingSample& s) { samples.push_back(s); });
  for (const TrackingSample& s : samples) {
    EXPECT_EQ(s.unreachable[0], s.t_s >= 1.0 - 1e-9) << s.t_s;  // at full pressure from the first tick
    EXPECT_FALSE(s.unreachable[1]);
  }
  // A reachable target (the scripted angle gets there) is never flagged.
  ScriptedPlant plant2;
  FixedController controller2({100.0, 0.0, 0.0, 0.0});
  const StepTrajectory near({{10.0, 0.0}}, 3.0);
  run_tracking(plant2, controller2, near, {}, [&](const TrackingSample& s) { EXPECT_FALSE(s.unreachable[0]); });
  EXPECT_THROW(run_tracking(plant2, controller2, near, {.unreachable_dwell_s = -1.0}, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace softwrist::control
