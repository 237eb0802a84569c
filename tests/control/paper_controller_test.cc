// The paper's antagonistic feedback controller (Section Control system, Fig. Control), on hand-computed sequences.

#include "control/paper_controller.h"

#include <cmath>

#include <gtest/gtest.h>

namespace softwrist::control {
namespace {

// Starting at 13.8 kPa everywhere, a +10 deg flexion error adds G * 10 = 0.083 kPa to the flexor and takes it from
// the extensor (at the threshold, not above it: normal rate). Reversed, the flexor is above 13.8 kPa and releases
// twice as fast (0.166 kPa) until it is back at the threshold. The idle ulnar/radial pair does not move.
TEST(PaperController, UpdateRuleOnAHandComputedSequence) {
  PaperController controller;
  const WristAngles zero{};
  struct Step {
    double desired_fe, flexor, extensor;
  };
  const Step steps[] = {{10.0, 13.883, 13.717},
                        {10.0, 13.966, 13.634},
                        {-10.0, 13.800, 13.717},
                        {-10.0, 13.717, 13.800},
                        {-10.0, 13.634, 13.883}};
  for (const Step& s : steps) {
    const Pressures& p = controller.update({.fe_deg = s.desired_fe, .ur_deg = 0.0}, zero);
    EXPECT_NEAR(p[0], s.flexor, 1e-12);
    EXPECT_NEAR(p[1], s.extensor, 1e-12);
    EXPECT_EQ(p[2], 13.8);
    EXPECT_EQ(p[3], 13.8);
  }
  // Ulnar/radial: the error uses the measured angle, 5 deg past a 0 deg goal means a radial (negative) correction.
  const Pressures& p = controller.update({.fe_deg = 0.0, .ur_deg = 0.0}, {.fe_deg = 0.0, .ur_deg = 5.0});
  EXPECT_NEAR(p[3], 13.8 + 0.0083 * 5.0, 1e-12);
  EXPECT_NEAR(p[2], 13.8 - 0.0083 * 5.0, 1e-12);
  controller.reset();
  for (double v : controller.pressures()) EXPECT_EQ(v, 13.8);
}

// Large errors for a long time: pressures stay within [0, 137] kPa; a NaN reading changes nothing.
TEST(PaperController, PressuresNeverLeaveTheRegulatorRange) {
  PaperController controller;
  for (int i = 0; i < 200000; ++i) {
    const double desired = (i / 50000) % 2 ? 90.0 : -90.0;
    for (double v : controller.update({desired, -desired}, {})) {
      ASSERT_GE(v, 0.0);
      ASSERT_LE(v, 137.0);
    }
  }
  EXPECT_EQ(controller.pressures()[0], 137.0);  // the last phase pushed flexion
  EXPECT_EQ(controller.pressures()[1], 0.0);
  const Pressures before = controller.pressures();
  EXPECT_EQ(controller.update({NAN, 0.0}, {}), before);
  EXPECT_THROW(PaperController({.period_s = 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace softwrist::control
