// The simulated plant: the IMU pair's angles from the bodies' relative orientation, its sampling and noise, and
// the command contract (control/plant.h).

#include "sim/simulated_plant.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physics/units.h"
#include "sim/model_builder.h"

namespace softwrist::sim {
namespace {

const Model& paper_model() {
  static const PluginSet plugins = PluginSet::Default();
  static const Model model = Model::FromXml(build_model_xml(paper_device()), plugins);
  return model;
}

// Without bias and noise the IMU angles are the joint angles, over both axes together.
TEST(SimulatedPlant, ImuAnglesAreTheJointAnglesWithoutBiasOrNoise) {
  SimulatedPlant plant(paper_model(), 137.0, {.noise_std_deg = 0.0, .bias_limit_deg = 0.0});
  for (double fe : {-50.0, -10.0, 0.0, 25.0, 70.0}) {
    for (double ur : {-20.0, 0.0, 15.0, 35.0}) {
      plant.wrist().run_held(0.005, units::deg_to_rad(fe), units::deg_to_rad(ur));
      const auto imu = plant.ideal_imu_angles();
      EXPECT_NEAR(imu.fe_deg, fe, 1e-9) << fe << " " << ur;
      EXPECT_NEAR(imu.ur_deg, ur, 1e-9) << fe << " " << ur;
      plant.wait_until(plant.time_s() + 0.02);
      ASSERT_TRUE(plant.read_angles().valid);
      EXPECT_LE(plant.time_s() - plant.read_angles().time_s, 0.01 + 1e-9);  // never older than one IMU period
    }
  }
}

// 100 Hz: between samples the reading holds; the bias stays within +-2.5 deg; noise has the configured spread.
TEST(SimulatedPlant, SamplesAt100HzWithBoundedBiasAndNoise) {
  SimulatedPlant plant(paper_model(), 137.0, {.noise_std_deg = 0.2, .bias_limit_deg = 2.5, .seed = 3});
  double sum = 0.0, sum_sq = 0.0, last_time = -1.0;
  int samples = 0;
  for (int step = 1; step <= 2000; ++step) {
    plant.wait_until(step * 0.001);
    const auto reading = plant.read_angles();
    if (reading.time_s != last_time) {
      EXPECT_NEAR(reading.time_s - (last_time < 0 ? reading.time_s : last_time), last_time < 0 ? 0.0 : 0.01, 1e-9);
      last_time = reading.time_s;
      const double error = reading.angles.fe_deg - plant.true_angles().fe_deg;
      sum += error;
      sum_sq += error * error;
      ++samples;
    }
  }
  EXPECT_NEAR(samples, 200, 1);
  const double mean = sum / samples;
  const double std = std::sqrt(sum_sq / samples - mean * mean);
  EXPECT_LE(std::abs(mean), 2.5 + 0.1);
  EXPECT_NEAR(std, 0.2, 0.05);
}

// control/plant.h's contract: a command outside the regulator range, or NaN, vents and throws naming the muscle.
TEST(SimulatedPlant, ACommandOutsideTheRangeVentsAndThrowsNamingTheMuscle) {
  SimulatedPlant plant(paper_model(), 137.0, {.noise_std_deg = 0.0, .bias_limit_deg = 0.0});
  plant.command_pressures_kpa({137.0, 0.0, 0.0, 50.0});  // the ends of the range are in it
  plant.wait_until(1.5);
  EXPECT_NEAR(plant.wrist().regulated_pressure_kpa(kFlexor), 137.0, 0.1);
  EXPECT_NEAR(plant.wrist().regulated_pressure_kpa(kRadial), 50.0, 0.1);
  for (const control::Pressures& bad :
       {control::Pressures{500.0, 0.0, 0.0, 50.0}, control::Pressures{0.0, -20.0, 0.0, 0.0},
        control::Pressures{0.0, 0.0, NAN, 0.0}}) {
    plant.command_pressures_kpa({137.0, 0.0, 0.0, 50.0});
    try {
      plant.command_pressures_kpa(bad);
      ADD_FAILURE() << "no fault";
    } catch (const control::PlantFault& e) {
      const std::string muscle = bad[0] != 0.0 ? "flexor" : bad[1] != 0.0 ? "extensor" : "ulnar";
      EXPECT_NE(std::string(e.what()).find(muscle), std::string::npos) << e.what();
    }
    plant.wait_until(plant.time_s() + 1.5);
    for (auto m : {kFlexor, kExtensor, kUlnar, kRadial}) EXPECT_NEAR(plant.wrist().regulated_pressure_kpa(m), 0.0, 0.1);
  }
}

}  // namespace
}  // namespace softwrist::sim
