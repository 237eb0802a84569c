#include "physics/antagonistic_pair.h"

#include <gtest/gtest.h>

#include "physics/paper_parameters.h"
#include "physics/units.h"

namespace softwrist::physics {
namespace {

using units::deg_to_rad;

AntagonisticPair symmetric_pair() { return {paper::design_optimum_flexor(), paper::design_optimum_flexor()}; }

// Section Torque applied by the exosuit: the net torque is the sum of the antagonists' torques, each muscle seeing
// the joint angle in its own direction.
TEST(AntagonisticPair, NetTorqueIsAgonistMinusAntagonistInOwnDirections) {
  const auto pair = symmetric_pair();
  for (double deg : {-40.0, -10.0, 0.0, 15.0, 45.0}) {
    const double theta = deg_to_rad(deg);
    const auto result = pair_torque(pair, theta, 100e3, 30e3);
    EXPECT_DOUBLE_EQ(result.agonist.torque, muscle_state(pair.agonist, theta, 100e3).torque);
    EXPECT_DOUBLE_EQ(result.antagonist.torque, muscle_state(pair.antagonist, -theta, 30e3).torque);
    EXPECT_DOUBLE_EQ(result.net_torque, result.agonist.torque - result.antagonist.torque);
  }
}

TEST(AntagonisticPair, SymmetricPairIsOddInAngleAndBalancedAtNeutral) {
  const auto pair = symmetric_pair();
  EXPECT_NEAR(pair_torque(pair, 0.0, 60e3, 60e3).net_torque, 0.0, 1e-12);
  for (double deg : {5.0, 20.0, 50.0}) {
    EXPECT_NEAR(pair_torque(pair, deg_to_rad(deg), 60e3, 60e3).net_torque,
                -pair_torque(pair, deg_to_rad(-deg), 60e3, 60e3).net_torque, 1e-12);
  }
  EXPECT_GT(pair_torque(pair, 0.0, 137e3, 0.0).net_torque, 0.0);
  EXPECT_LT(pair_torque(pair, 0.0, 0.0, 137e3).net_torque, 0.0);
}

TEST(WristMuscles, SelectsThePairOfEachAxis) {
  const WristMuscles muscles{symmetric_pair(),
                             {paper::rom_muscle(paper::rom_table()[2]), paper::rom_muscle(paper::rom_table()[3])}};
  EXPECT_EQ(&muscles.pair(WristAxis::kFlexionExtension), &muscles.flexion_extension);
  EXPECT_EQ(&muscles.pair(WristAxis::kUlnarRadial), &muscles.ulnar_radial);
}

}  // namespace
}  // namespace softwrist::physics
