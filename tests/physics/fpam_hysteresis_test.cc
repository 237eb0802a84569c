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
  const double force = 123.4;
  for (const double s : {-1.0, 0.0, 0.7, 1.0}) EXPECT_EQ(hysteretic_force({.fraction = 0.0}, force, s), force);
  const FpamHysteresis h{.fraction = 0.15};
  EXPECT_NEAR(hysteretic_force(h, force, 1.0) - hysteretic_force(h, force, -1.0), 2.0 * 0.15 * force, 1e-12);
  // An explicit step that overshoots the bound is clamped.
  EXPECT_EQ(hysteretic_force(h, force, 1.2), hysteretic_force(h, force, 1.0));
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
}

}  // namespace
}  // namespace softwrist::physics
