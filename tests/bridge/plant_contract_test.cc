// control/plant.h's contract, checked against both plants with one typed test: the simulation (sim::SimulatedPlant)
// and the bridge (bridge::BridgePlant) over the device emulator on the lock-step rig. A controller must see the same
// behaviour on either: in-range commands move the wrist; a command outside [0, max] kPa or NaN vents every muscle and
// throws control::PlantFault naming the muscle.

#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "bridge/bridge_plant.h"
#include "bridge_apps/device_emulator.h"
#include "bridge_apps/lockstep_link.h"
#include "control/plant.h"
#include "experiments/simulated_device.h"
#include "sim/device.h"
#include "sim/simulated_plant.h"
#include "support/emulator_test_support.h"

namespace softwrist {
namespace {

// The range-of-motion device in simulation, the hand on the table, ideal IMUs.
class SimulatedPlantRig {
 public:
  SimulatedPlantRig()
      : device_(sim::load_device(SOFTWRIST_SOURCE_DIR "/models/rom_device.json"), sim::ModelOptions{.gravity = 0.0}),
        plant_(device_.model, 137.0, {.noise_std_deg = 0.0, .bias_limit_deg = 0.0}) {}
  control::Plant& plant() { return plant_; }
  bool vented() {  // the regulators empty once commanded to 0
    plant_.wait_until(plant_.time_s() + 1.0);
    for (auto m : {sim::kFlexor, sim::kExtensor, sim::kUlnar, sim::kRadial}) {
      if (plant_.wrist().regulated_pressure_kpa(m) > 0.1) return false;
    }
    return true;
  }

 private:
  experiments::SimulatedDevice device_;
  sim::SimulatedPlant plant_;
};

// The same device behind the emulated firmware, the host's bridge on the lock-step rig's clock.
class BridgePlantRig {
 public:
  BridgePlantRig()
      : emulator_(testing::nominal_emulator_config()),
        link_(emulator_),
        plant_(std::make_unique<bridge::BridgePlant>(link_.open_host(), link_)) {
    plant_->start_session();
  }
  control::Plant& plant() { return *plant_; }
  bool vented() {  // the device's own record: every setpoint 0, and why
    link_.run_for_ms(5);
    return emulator_.stats().vented && !emulator_.stats().vents.empty();
  }

 private:
  bridge::DeviceEmulator emulator_;
  bridge::LockstepLink link_;
  std::unique_ptr<bridge::BridgePlant> plant_;
};

template <class Rig>
class PlantContract : public ::testing::Test {
 protected:
  // A constant command every 14 ms (the paper's loop period) for `seconds`.
  void hold(const control::Pressures& p, double seconds) {
    control::Plant& plant = rig_.plant();
    const double start = plant.time_s();
    for (double t = 0.0; t < seconds; t += 0.014) {
      plant.command_pressures_kpa(p);
      plant.wait_until(start + t + 0.014);
    }
  }
  Rig rig_;
};

using Rigs = ::testing::Types<SimulatedPlantRig, BridgePlantRig>;
TYPED_TEST_SUITE(PlantContract, Rigs);

TYPED_TEST(PlantContract, TheRangeIsTheRegulatorsAndItsEndsAreCommands) {
  control::Plant& plant = this->rig_.plant();
  EXPECT_DOUBLE_EQ(plant.max_pressure_kpa(), 137.0);
  this->hold({0.0, 0.0, 0.0, 0.0}, 0.5);
  this->hold({137.0, 0.0, 0.0, 0.0}, 1.5);
  const control::ImuReading reading = plant.read_angles();
  ASSERT_TRUE(reading.valid);
  EXPECT_GT(reading.angles.fe_deg, 10.0) << "the flexor at full pressure flexes the wrist";
}

TYPED_TEST(PlantContract, ACommandOutsideTheRangeOrNanVentsAndThrowsNamingTheMuscle) {
  const struct {
    control::Pressures command;
    std::string muscle;
  } bad[] = {
      {{60.0, 137.5, 0.0, 0.0}, "extensor"}, {{60.0, 0.0, -1.0, 0.0}, "ulnar"}, {{60.0, 0.0, 0.0, NAN}, "radial"}};
  for (const auto& b : bad) {
    TypeParam rig;  // a fresh plant each time: a fault may end the bridge's session
    control::Plant& plant = rig.plant();
    plant.command_pressures_kpa({60.0, 0.0, 0.0, 0.0});
    plant.wait_until(plant.time_s() + 0.014);
    try {
      plant.command_pressures_kpa(b.command);
      ADD_FAILURE() << b.muscle << ": no fault";
    } catch (const control::PlantFault& e) {
      EXPECT_NE(std::string(e.what()).find(b.muscle), std::string::npos) << e.what();
    }
    EXPECT_TRUE(rig.vented()) << b.muscle;
  }
}

}  // namespace
}  // namespace softwrist
