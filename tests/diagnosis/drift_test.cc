// A gap that drifts over the session (diagnosis/drift.h): the last repetition of each condition against the first.
// A tensile test of three cycles at five pressures, two directions and 34 contraction steps (340 conditions, as a
// real rig logs them), its noise white, or with a wander of half its size correlated over 20 conditions of a cycle (a
// load cell's slow drift), with and without a creep that lowers every reading cycle by cycle.

#include "diagnosis/drift.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace softwrist::diagnosis {
namespace {

constexpr int kCycles = 3, kConditions = 340;
constexpr double kNoise = 0.3;  // [N] one reading's

// The trial's points (group = condition, repetition = cycle) and its residuals as predictions of zero: noise, a
// wander common to neighbouring conditions of a cycle, and `creep` per cycle (cycle k reads k x creep).
struct Case {
  std::vector<PreparedTrial> prepared;
  std::vector<std::vector<double>> predictions;
};

Case tensile(double creep, double wander, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  PreparedTrial trial{.name = "tensile/trials", .unit = "N", .noise = kNoise};
  for (int cycle = 0; cycle < kCycles; ++cycle) {
    double slow = 0.0;
    for (int c = 0; c < kConditions; ++c) {
      slow = 0.95 * slow + std::sqrt(1.0 - 0.95 * 0.95) * wander * normal(rng);  // AR(1), 20 conditions' memory
      trial.points.push_back(
          Point{.measured = cycle * creep + slow + kNoise * normal(rng), .group = c, .repetition = cycle});
    }
  }
  return {{trial}, {std::vector<double>(trial.points.size(), 0.0)}};
}

TEST(Drift, NoneInWhiteNoiseNorInAWanderCommonToNeighbouringConditions) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    for (const double wander : {0.0, 0.15}) {
      const Case c = tensile(0.0, wander, seed);
      const auto drift = drift_across_repetitions(c.prepared, c.predictions);
      ASSERT_EQ(drift.size(), 1u);
      EXPECT_EQ(drift[0].conditions, static_cast<std::size_t>(kConditions));
      EXPECT_EQ(drift[0].first_repetition, 0);
      EXPECT_EQ(drift[0].last_repetition, kCycles - 1);
      EXPECT_FALSE(drift[0].significant) << "seed " << seed << " wander " << wander << ": t " << drift[0].t;
    }
  }
}

// A creep of 0.25 N per cycle (0.5 N, 1.7 noise units, from the first cycle to the last) is found in white noise, and
// one of 0.4 N per cycle (2.7 noise units) through a wander of a third of the noise, with their sign and size. (Through
// that wander the smaller creep reads t = -7 to -8, below the test's 8.6: the batch means see the wander.)
TEST(Drift, ACreepOverTheCyclesIsFoundWithItsSizeAndSign) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    for (const auto& [creep, wander] : {std::pair{-0.25, 0.0}, std::pair{-0.4, 0.1}}) {
      const Case c = tensile(creep, wander, seed);
      const auto drift = drift_across_repetitions(c.prepared, c.predictions);
      ASSERT_EQ(drift.size(), 1u);
      EXPECT_TRUE(drift[0].significant) << "seed " << seed << " creep " << creep << ": t " << drift[0].t;
      EXPECT_NEAR(drift[0].shift, 2.0 * creep / kNoise, 0.5) << "seed " << seed;  // the wander moves it by ~0.2
    }
  }
}

// Below half a noise unit it is not the gap's cause, however certain; a trial of one repetition, or with fewer than
// ten repeated conditions, has no drift to test.
TEST(Drift, SmallOrUntestableDriftsAreNotSignificant) {
  const Case small = tensile(-0.05, 0.0, 3);
  EXPECT_FALSE(drift_across_repetitions(small.prepared, small.predictions)[0].significant);

  Case one = tensile(-0.25, 0.0, 4);
  for (auto& p : one.prepared[0].points) p.repetition = 0;
  EXPECT_TRUE(drift_across_repetitions(one.prepared, one.predictions).empty());

  Case few = tensile(-1.0, 0.0, 5);
  std::erase_if(few.prepared[0].points, [](const Point& p) { return p.group >= 8; });
  few.predictions[0].resize(few.prepared[0].points.size());
  const auto drift = drift_across_repetitions(few.prepared, few.predictions);
  ASSERT_EQ(drift.size(), 1u);
  EXPECT_EQ(drift[0].conditions, 8u);
  EXPECT_FALSE(drift[0].significant);
}

}  // namespace
}  // namespace softwrist::diagnosis
