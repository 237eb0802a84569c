// Torque demand to pair pressures through the torque model (control/pressure_allocation.h).

#include "control/pressure_allocation.h"

#include <gtest/gtest.h>

#include "physics/units.h"
#include "sim/device.h"
#include "sim/wrist_statics.h"

namespace softwrist::control {
namespace {

using physics::WristAxis;
constexpr double kMax = 137e3, kCo = 5e3;

// Along the co-contraction path the agonist rises while the antagonist falls, the ends are (max, 0) and (0, max),
// and s = 0 is co-contraction.
TEST(PressureAllocation, PathRunsFromFullAntagonistThroughCoContractionToFullAgonist) {
  EXPECT_EQ(pressures_on_path(0.0, kCo, kMax).agonist, kCo);
  EXPECT_EQ(pressures_on_path(0.0, kCo, kMax).antagonist, kCo);
  EXPECT_EQ(pressures_on_path(1.0, kCo, kMax).agonist, kMax);
  EXPECT_EQ(pressures_on_path(1.0, kCo, kMax).antagonist, 0.0);
  EXPECT_EQ(pressures_on_path(-1.0, kCo, kMax).agonist, 0.0);
  EXPECT_EQ(pressures_on_path(-1.0, kCo, kMax).antagonist, kMax);
  EXPECT_EQ(pressures_on_path(7.0, kCo, kMax).agonist, kMax);  // clamped
  double last_agonist = -1.0, last_antagonist = 1e9;
  for (double s = -1.0; s <= 1.0; s += 0.01) {
    const PairPressures p = pressures_on_path(s, kCo, kMax);
    EXPECT_GE(p.agonist, last_agonist);
    EXPECT_LE(p.antagonist, last_antagonist);
    last_agonist = p.agonist;
    last_antagonist = p.antagonist;
  }
}

// The allocated pressures give the demanded torque in the pair's own torque model (antagonistic_pair.h), on both
// axes and across the range; demands beyond the pair's reach saturate at the right end, flagged.
TEST(PressureAllocation, MeetsTheDemandThroughThePairTorqueModel) {
  const physics::WristModel wrist = sim::wrist_model(sim::rom_device());
  for (WristAxis axis : {WristAxis::kFlexionExtension, WristAxis::kUlnarRadial}) {
    const auto& pair = wrist.muscles.pair(axis);
    for (double angle_deg : {-20.0, -5.0, 0.0, 8.0, 15.0}) {
      const double angle = units::deg_to_rad(angle_deg);
      const double strongest = physics::pair_torque(pair, angle, kMax, 0.0).net_torque;
      const double weakest = physics::pair_torque(pair, angle, 0.0, kMax).net_torque;
      ASSERT_LT(weakest, strongest);
      for (double f : {0.05, 0.3, 0.5, 0.7, 0.95}) {
        const double demand = weakest + f * (strongest - weakest);
        const PairPressures p = allocate_pair_pressures(wrist, axis, angle, demand, kCo, kMax);
        EXPECT_EQ(p.saturated, 0);
        EXPECT_NEAR(physics::pair_torque(pair, angle, p.agonist, p.antagonist).net_torque, demand, 1e-6)
            << angle_deg << " " << f;
        EXPECT_GE(std::min(p.agonist, p.antagonist), 0.0);
        EXPECT_LE(std::max(p.agonist, p.antagonist), kMax);
      }
      const PairPressures high = allocate_pair_pressures(wrist, axis, angle, strongest + 1.0, kCo, kMax);
      EXPECT_EQ(high.saturated, 1);
      EXPECT_EQ(high.agonist, kMax);
      const PairPressures low = allocate_pair_pressures(wrist, axis, angle, weakest - 1.0, kCo, kMax);
      EXPECT_EQ(low.saturated, -1);
      EXPECT_EQ(low.antagonist, kMax);
    }
  }
}

}  // namespace
}  // namespace softwrist::control
