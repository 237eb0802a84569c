#include "control/excitation_controller.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softwrist::control {
namespace {

using ::testing::HasSubstr;

// The default routine is what docs/calibration.md promises: at most two minutes, never outside the regulators'
// range, no edge steeper than asked (the device's own rate limit is 1370 kPa/s), and each muscle alone at each level.
TEST(ExcitationRoutine, DefaultRoutineIsShortSafeAndExcitesEachMuscleAlone) {
  const ExcitationRoutineParameters p;
  const auto routine = excitation_routine(p, 137.0);
  EXPECT_LE(routine_duration_s(routine), 120.0);
  EXPECT_GE(routine_duration_s(routine), 90.0);
  EXPECT_LE(routine_max_ramp_kpa_s(routine), p.edge_rate_kpa_s + 1e-9);
  std::set<std::pair<int, double>> alone;  // (muscle, level) held with the others vented
  for (const auto& s : routine) {
    for (int m = 0; m < 4; ++m) {
      for (double kpa : {s.from_kpa[m], s.to_kpa[m]}) {
        EXPECT_GE(kpa, 0.0);
        EXPECT_LE(kpa, 137.0);
      }
    }
    const int active =
        static_cast<int>(std::count_if(s.to_kpa.begin(), s.to_kpa.end(), [](double v) { return v > 0; }));
    if (active == 1 && s.from_kpa == s.to_kpa) {
      const int m = static_cast<int>(std::find_if(s.to_kpa.begin(), s.to_kpa.end(), [](double v) { return v > 0; }) -
                                     s.to_kpa.begin());
      alone.insert({m, s.to_kpa[m]});
    }
  }
  for (int m = 0; m < 4; ++m) {
    for (double level : p.step_levels_kpa) EXPECT_TRUE(alone.contains({m, level})) << m << " at " << level;
  }
}

TEST(ExcitationController, PlaysItsScheduleAndVentsAfterIt) {
  const std::vector<ExcitationSegment> segments = {{1.0, {0, 0, 0, 0}, {100, 0, 0, 0}, "ramp"},
                                                   {2.0, {0, 50, 0, 0}, {0, 50, 0, 0}, "hold"}};
  ExcitationController c(segments, 137.0);
  EXPECT_DOUBLE_EQ(c.duration_s(), 3.0);
  EXPECT_NEAR(c.command(0.25, {}, {})[0], 25.0, 1e-12);  // a quarter of the way up the ramp
  EXPECT_DOUBLE_EQ(c.command(2.0, {}, {})[1], 50.0);
  EXPECT_DOUBLE_EQ(c.command(2.0, {}, {})[0], 0.0);
  EXPECT_EQ(c.command(3.5, {}, {}), (Pressures{0, 0, 0, 0}));
}

TEST(ExcitationController, RefusesPressuresOutsideTheRegulatorsRange) {
  const std::vector<ExcitationSegment> too_high = {{1.0, {0, 0, 0, 0}, {0, 0, 150, 0}, "x"}};
  try {
    ExcitationController c(too_high, 137.0);
    FAIL() << "accepted 150 kPa";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("ulnar pressure 150 kPa is outside 0..137 kPa"));
  }
  EXPECT_THROW(ExcitationController({}, 137.0), std::invalid_argument);
  EXPECT_THROW(ExcitationController({{0.0, {}, {}, "x"}}, 137.0), std::invalid_argument);
  ExcitationRoutineParameters p;
  p.step_levels_kpa = {45, 200};
  EXPECT_THROW(excitation_routine(p, 137.0), std::invalid_argument);
  p.step_levels_kpa = {45};
  p.edge_rate_kpa_s = 0.0;
  EXPECT_THROW(excitation_routine(p, 137.0), std::invalid_argument);
}

}  // namespace
}  // namespace softwrist::control
