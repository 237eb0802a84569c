// The fabric's hysteresis as a state (physics/fpam_hysteresis.h): Dahl's model with exponent 1 against its closed-form
// solution, the static law at h = 0, and the loop's width.

#include "physics/fpam_hysteresis.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physics/errors.h"

namespace softwrist::physics {
namespace {

// Integrates ds/dt over a length change at a constant rate, in small explicit steps (as MuJoCo's Euler step does).
double integrate(const FpamHysteresis& h, double state, double length_change, double rate = 0.01) {
  const double dt = 1e-4;
  const int steps = static_cast<int>(std::round(std::abs(length_change) / rate / dt));
  const double v = length_change > 0.0 ? rate : -rate;
  for (int i = 0; i < steps; ++i) state += dt * hysteresis_state_rate(h, state, v);
  return state;
}

// Dahl with exponent 1 from s0 over a length change x of one sign: s = sign(x) + (s0 - sign(x)) exp(-|x| / l_h).
TEST(FpamHysteresis, StateFollowsDahlsClosedForm) {
  const FpamHysteresis h{.fraction = 0.1, .transition_length = 0.002};
  for (const double x : {0.0005, 0.002, 0.006, -0.001, -0.004}) {
    for (const double s0 : {-1.0, -0.3, 0.0, 0.5, 1.0}) {
      const double sign = x > 0.0 ? 1.0 : -1.0;
      const double expected = sign + (s0 - sign) * std::exp(-std::abs(x) / h.transition_length);
      EXPECT_NEAR(integrate(h, s0, x), expected, 2e-3) << "x " << x << " s0 " << s0;
    }
  }
}

// Rate-independent: the same length change at a tenth of the speed gives the same state, and a still muscle keeps it.
TEST(FpamHysteresis, RateIndependentAndHeldAtRest) {
  const FpamHysteresis h{.fraction = 0.2, .transition_length = 0.003};
  EXPECT_NEAR(integrate(h, 0.0, 0.004, 0.01), integrate(h, 0.0, 0.004, 0.001), 1e-3);
  for (const double s : {-0.8, 0.0, 0.6}) EXPECT_EQ(hysteresis_state_rate(h, s, 0.0), 0.0);
  // At a bound, moving on the same way leaves it there: the state never leaves [-1, 1].
  EXPECT_EQ(hysteresis_state_rate(h, 1.0, 0.05), 0.0);
  EXPECT_EQ(hysteresis_state_rate(h, -1.0, -0.05), 0.0);
}

// h = 0 is the paper's static law (Eqn. force) on either branch; a full loop's width at one length is 2 h F.
TEST(FpamHysteresis, StaticLawAtZeroAndLoopWidthTwoHF) {
  const double force = 123.4, end_force = 70.0;
  for (const double s : {-1.0, 0.0, 0.7, 1.0})
    EXPECT_EQ(hysteretic_force({.fraction = 0.0}, force, s, end_force), force);
  const FpamHysteresis h{.fraction = 0.15};
  EXPECT_NEAR(hysteretic_force(h, force, 1.0, end_force) - hysteretic_force(h, force, -1.0, end_force),
              2.0 * 0.15 * force, 1e-12);
  // An explicit step that overshoots the bound is clamped.
  EXPECT_EQ(hysteretic_force(h, force, 1.2, end_force), hysteretic_force(h, force, 1.0, end_force));
}

// The dry friction (Tondu & Lopez 2000: a level that grows with pressure) adds F_0 + mu pi r0^2 P to the loading
// branch and takes it from the unloading one, whatever the pull; it never exceeds the pull, so a slack muscle (F = 0)
// pulls nothing on either branch and the unloading branch reaches zero, never below.
TEST(FpamHysteresis, DryFrictionGrowsWithPressureAndIsBoundedByThePull) {
  const FpamHysteresis h{.friction_force = 1.5, .pressure_friction = 0.05};
  const double end_force = 80.0;  // pi r0^2 P [N]
  EXPECT_TRUE(h.active());
  EXPECT_NEAR(hysteretic_force(h, 60.0, 1.0, end_force), 60.0 + 1.5 + 0.05 * 80.0, 1e-12);
  EXPECT_NEAR(hysteretic_force(h, 60.0, -1.0, end_force), 60.0 - 5.5, 1e-12);
  EXPECT_NEAR(hysteretic_force(h, 60.0, 0.5, end_force), 60.0 + 0.5 * 5.5, 1e-12);
  // The same level at a tenth of the pull: the loop keeps its absolute width (unlike h F).
  EXPECT_NEAR(hysteretic_force(h, 20.0, 1.0, end_force) - hysteretic_force(h, 20.0, -1.0, end_force), 11.0, 1e-12);
  EXPECT_EQ(hysteretic_force(h, 0.0, 1.0, end_force), 0.0);
  EXPECT_NEAR(hysteretic_force(h, 3.0, 1.0, end_force), 6.0, 1e-12);
  EXPECT_EQ(hysteretic_force(h, 3.0, -1.0, end_force), 0.0);
}

// A rig that moves in steps advances the state by Dahl's closed form, the same as the rate law integrated.
TEST(FpamHysteresis, StateAfterAStepIsTheIntegratedRateLaw) {
  const FpamHysteresis h{.fraction = 0.1, .transition_length = 0.003};
  for (const double x : {0.001, 0.004, -0.002, -0.009}) {
    for (const double s0 : {-1.0, -0.2, 0.4, 1.0}) {
      EXPECT_NEAR(hysteresis_state_after(h, s0, x), integrate(h, s0, x), 2e-3) << x << " " << s0;
    }
  }
  EXPECT_EQ(hysteresis_state_after(h, 0.3, 0.0), 0.3);
}

TEST(FpamHysteresis, ValidateNamesTheField) {
  EXPECT_NO_THROW(validate(FpamHysteresis{.fraction = 0.3}));
  for (const double bad : {-0.1, 0.5, 0.9, std::nan("")}) {
    try {
      validate(FpamHysteresis{.fraction = bad});
      ADD_FAILURE() << bad;
    } catch (const InvalidParameter& e) {
      EXPECT_NE(std::string(e.what()).find("hysteresis"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(validate(FpamHysteresis{.fraction = 0.1, .transition_length = 0.0}), InvalidParameter);
  EXPECT_THROW(validate(FpamHysteresis{.friction_force = -1.0}), InvalidParameter);
  EXPECT_THROW(validate(FpamHysteresis{.pressure_friction = 1.0}), InvalidParameter);
  EXPECT_THROW(validate(FpamHysteresis{.pressure_friction = std::nan("")}), InvalidParameter);
}

}  // namespace
}  // namespace softwrist::physics
