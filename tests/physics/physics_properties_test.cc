// Property tests over random valid inputs: the physics core never returns NaN, never a negative force, and its
// invariants (stretching never adds force, torque continuous at the transition) hold everywhere, not only at the
// paper's numbers. Fixed seed: a failure reproduces.

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "physics/fpam_force.h"
#include "physics/muscle_torque.h"
#include "physics/units.h"

namespace softwrist::physics {
namespace {

using units::deg_to_rad;

struct RandomMuscles {
  std::mt19937_64 rng{20261122};
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

  // Placements within the bounds of Table optimized_parameters, wrist radii 1-3 cm (below both mounts), fPAMs
  // with eps_max up to the Eqn. fiber_orientation bound, L0 from Eqn. length at a random extension.
  Muscle next(StretchMode mode) {
    const Placement placement{
        .d1 = uniform(0.02, 0.22), .w1 = uniform(0.035, 0.05), .d2 = uniform(0.015, 0.09), .w2 = uniform(0.015, 0.035)};
    const double r_w = uniform(0.01, std::min(0.03, 0.99 * std::hypot(placement.d2, placement.w2)));
    const double rest = rest_length_for_range(placement, r_w, deg_to_rad(uniform(-90.0, -30.0)));
    // Drawn in this order (the properties' random devices stay the same).
    const double rest_length = rest * uniform(0.95, 1.05);
    const double r0 = uniform(0.005, 0.02), eps_max = uniform(0.05, 0.42);
    const double k1 = uniform(1e4, 1e7), k2 = -uniform(1e4, 1e8);
    return Muscle{{.fpam = FpamParameters::Constant(r0, eps_max),
                   .rest_length = rest_length,
                   .stretch_mode = mode,
                   .mount_stiffness = {k1, k2}},
                  placement,
                  r_w};
  }
};

TEST(PhysicsProperties, ForceFiniteAndNonNegativeEverywhere) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> eps_max(0.01, 0.42), eps(-0.3, 0.9), pressure(0.0, 448e3), radius(1e-3, 0.05);
  for (int i = 0; i < 20000; ++i) {
    const FpamCoefficients c{radius(rng), eps_max(rng)};
    const double f = fpam_force(pressure(rng), eps(rng), c, FabricProperties{});
    ASSERT_TRUE(std::isfinite(f));
    ASSERT_GE(f, 0.0);
  }
}

TEST(PhysicsProperties, MuscleStateFiniteAndStretchNeverAddsForce) {
  RandomMuscles random;
  for (int i = 0; i < 3000; ++i) {
    const Muscle fixed = random.next(StretchMode::kNone);
    Muscle stretched = fixed;
    stretched.stretch_mode = StretchMode::kSelfConsistent;
    Muscle once = fixed;
    once.stretch_mode = StretchMode::kOneShot;
    const double theta = deg_to_rad(random.uniform(-90.0, 90.0));
    const double pressure = random.uniform(0.0, 137e3);
    const auto a = muscle_state(fixed, theta, pressure);
    const auto b = muscle_state(stretched, theta, pressure);
    const auto c = muscle_state(once, theta, pressure);
    for (const auto& s : {a, b, c}) {
      ASSERT_TRUE(std::isfinite(s.torque) && std::isfinite(s.force) && std::isfinite(s.effective_length)) << i;
      ASSERT_GE(s.force, 0.0);
      ASSERT_LE(s.effective_length, s.path_length);
    }
    ASSERT_LE(b.force, a.force + 1e-9) << i;
    ASSERT_LE(c.force, b.force + 1e-9) << i;
  }
}

TEST(PhysicsProperties, TorqueContinuousAtTransitionForRandomPlacements) {
  RandomMuscles random;
  for (int i = 0; i < 2000; ++i) {
    const Muscle muscle = random.next(StretchMode::kSelfConsistent);
    const double theta = wrap_transition_angle(muscle.placement, muscle.wrist_radius);
    if (std::abs(theta) > deg_to_rad(170.0)) continue;
    const double pressure = random.uniform(0.0, 137e3);
    const auto before = muscle_state(muscle, theta - 1e-10, pressure);
    const auto after = muscle_state(muscle, theta + 1e-10, pressure);
    ASSERT_EQ(before.regime, Regime::kWrapping);
    ASSERT_EQ(after.regime, Regime::kStraight);
    ASSERT_NEAR(before.torque, after.torque, 1e-6 * (1.0 + std::abs(before.torque))) << i;
  }
}

}  // namespace
}  // namespace softwrist::physics
