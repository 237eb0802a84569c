// Model-level robustness, as property tests: placement files drawn at random over a wide range of valid devices
// (every field of docs/placement-file.md varied at once), driven with random pressures, never give a NaN force, a
// NaN or runaway state, or a MuJoCo instability warning, in the analytic model (src/physics) or in the simulation
// (MuJoCo with the fPAM plugin); and an invalid file is refused before any model is built, naming the field. A
// tendon grazing its wrap cylinder keeps a finite length (MuJoCo 2.2.2 alone gives it NaN there).

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "physics/muscle_torque.h"
#include "physics/units.h"
#include "sim/device.h"
#include "sim/model_builder.h"
#include "sim/wrist_sim.h"

namespace softwrist::sim {
namespace {

using ::testing::HasSubstr;
using units::cm_to_m;

double uniform(std::mt19937_64& rng, double low, double high) {
  return std::uniform_real_distribution<double>(low, high)(rng);
}

// A device drawn from ranges wider than any the paper or a user of it would place: mounts 4-26 cm from the joint
// and 0.5-5 cm off the skin, wrists of 1.5-4.5 cm radius, L0 from 90 % to 130 % of the neutral path, a constant or
// tabulated fPAM, any stretch mode with K from 5 to 200 N/cm^2, regulators of 60-200 kPa and 20-400 ms, a light
// or heavy, stiff or slack hand and wrist.
DeviceDescription random_device(std::mt19937_64& rng) {
  DeviceDescription device = paper_device();
  if (rng() % 2 == 0) {
    device.fpam = physics::FpamParameters::Constant(cm_to_m(uniform(rng, 0.6, 2.0)), uniform(rng, 0.1, 0.4));
  }
  for (auto& mount : device.muscles) {
    mount.placement = {cm_to_m(uniform(rng, 8.0, 26.0)), cm_to_m(uniform(rng, 0.5, 5.0)),
                       cm_to_m(uniform(rng, 4.0, 12.0)), cm_to_m(uniform(rng, 0.5, 5.0))};
    // The mounts lie outside the wrist (torque_geometry.h): r_w below either mount's distance from the joint.
    const double nearest_mount = std::min(std::hypot(mount.placement.d1, mount.placement.w1),
                                          std::hypot(mount.placement.d2, mount.placement.w2));
    mount.wrist_radius = uniform(rng, cm_to_m(1.5), std::min(cm_to_m(4.5), 0.95 * nearest_mount));
    const double neutral_path = physics::muscle_path(mount.placement, mount.wrist_radius, 0.0).length;
    mount.rest_length = neutral_path * uniform(rng, 0.9, 1.3);
  }
  device.stretch_mode = static_cast<physics::StretchMode>(rng() % 3);
  device.mount_stiffness = {-units::n_per_cm2_to_n_per_m2(uniform(rng, 5.0, 200.0)),
                            -units::n_per_cm2_to_n_per_m2(uniform(rng, 5.0, 200.0))};
  device.regulator = {.max_pressure = units::kpa_to_pa(uniform(rng, 60.0, 200.0)),
                      .time_constant = uniform(rng, 0.02, 0.4)};
  device.wrist.stiffness_fe = uniform(rng, 0.0, 4.0);
  device.wrist.stiffness_ur = uniform(rng, 0.0, 4.0);
  device.wrist.damping_fe = uniform(rng, 0.005, 0.2);
  device.wrist.damping_ur = uniform(rng, 0.005, 0.2);
  device.hand.mass = uniform(rng, 0.2, 0.8);
  device.hand.com_distance = cm_to_m(uniform(rng, 5.0, 12.0));
  return device;
}

TEST(ModelRobustness, RandomValidDevicesAndPressuresGiveFiniteForcesInTheAnalyticModel) {
  std::mt19937_64 rng(20261123);
  int accepted = 0;
  for (int trial = 0; trial < 200; ++trial) {
    DeviceDescription device = random_device(rng);
    // What a user's file goes through: written, read back and checked.
    try {
      device = parse_device(device_to_json(device), "random.json");
    } catch (const std::runtime_error& e) {
      ADD_FAILURE() << "a device drawn from the valid ranges was refused: " << e.what();
      continue;
    }
    ++accepted;
    for (int sample = 0; sample < 50; ++sample) {
      const int index = static_cast<int>(rng() % 4);
      const double angle = units::deg_to_rad(uniform(rng, -100.0, 100.0));
      const double pressure = uniform(rng, 0.0, device.regulator.max_pressure);
      const auto state = physics::muscle_state(device.muscle(index), angle, pressure);
      ASSERT_TRUE(std::isfinite(state.force) && std::isfinite(state.torque) && std::isfinite(state.moment_arm))
          << device_to_json(device) << "\nmuscle " << index << " at " << angle << " rad, " << pressure << " Pa";
      ASSERT_GE(state.force, 0.0);
      ASSERT_GE(state.mount_stretch, 0.0);
    }
  }
  EXPECT_EQ(accepted, 200);
}

TEST(ModelRobustness, RandomValidDevicesUnderRandomPressuresSimulateStably) {
  std::mt19937_64 rng(11232026);
  const PluginSet plugins = PluginSet::Default();
  for (int trial = 0; trial < 16; ++trial) {
    const DeviceDescription device = parse_device(device_to_json(random_device(rng)), "random.json");
    SCOPED_TRACE(device_to_json(device));
    const Model model = Model::FromXml(build_model_xml(device), plugins, "random.xml");
    WristSim sim(model);
    const double max_kpa = units::pa_to_kpa(device.regulator.max_pressure);
    // 2 s of pressures switched every 0.1 s among empty, full and anything between, antagonists against each other.
    for (int segment = 0; segment < 20; ++segment) {
      std::array<double, 4> pressures{};
      for (double& p : pressures) p = rng() % 4 == 0 ? max_kpa : rng() % 3 == 0 ? 0.0 : uniform(rng, 0.0, max_kpa);
      sim.command_pressures_kpa(pressures);
      sim.run(0.1);
      // Within the device's joint limits, give or take the give of MuJoCo's soft limits (default solref, 0.02 s:
      // 200 kPa muscles on long moment arms push up to ~20 deg past them), and no runaway speed.
      const double give = units::deg_to_rad(30.0);
      const std::array<std::pair<double, double>, 2> range = {
          std::pair{-device.wrist.extension_limit - give, device.wrist.flexion_limit + give},
          std::pair{-device.wrist.radial_limit - give, device.wrist.ulnar_limit + give}};
      for (physics::WristAxis joint : {physics::WristAxis::kFlexionExtension, physics::WristAxis::kUlnarRadial}) {
        const double angle = sim.angle(joint);
        ASSERT_TRUE(std::isfinite(angle) && std::isfinite(sim.velocity(joint))) << "segment " << segment;
        const auto [low, high] = range[joint == physics::WristAxis::kFlexionExtension ? 0 : 1];
        ASSERT_TRUE(angle > low && angle < high) << "segment " << segment << ": " << angle << " rad";
        ASSERT_LT(std::abs(sim.velocity(joint)), 100.0) << "segment " << segment;
      }
      for (int m = 0; m < 4; ++m) {
        const auto muscle = static_cast<MuscleIndex>(m);
        ASSERT_TRUE(std::isfinite(sim.muscle_torque(muscle))) << kMuscleNames[m] << ", segment " << segment;
        ASSERT_GE(sim.regulated_pressure_kpa(muscle), -1e-9);
        ASSERT_LE(sim.regulated_pressure_kpa(muscle), max_kpa + 1e-9);
      }
    }
    const mjData* d = sim.data();
    EXPECT_EQ(d->warning[mjWARN_BADQACC].number, 0) << "MuJoCo reset an unstable simulation";
    EXPECT_EQ(d->warning[mjWARN_BADQVEL].number, 0);
    EXPECT_EQ(d->warning[mjWARN_BADQPOS].number, 0);
  }
}

// MuJoCo 2.2.2 gives a spatial tendon whose straight path just grazes its wrap cylinder a NaN length (an unclamped
// acos of a cosine rounded above 1; WristSim::evaluate_clear_of_grazing_wraps). Model and pose are those where seed
// 14's elliptical_section diagnosis stopped: the idle extensor grazing its cylinder, the wrist held by the ulnar
// muscle at 137 kPa. MuJoCo alone gives NaN there; the simulation a finite length, and it steps on.
TEST(ModelRobustness, ATendonGrazingItsWrapCylinderKeepsAFiniteLength) {
  const Model model = Model::FromFile(SOFTWRIST_SOURCE_DIR "/tests/sim/data/grazing_wrap.xml", PluginSet::Default());
  constexpr double kFe = -0.10224725846181237, kUr = 0.2823603449519223;  // [rad], as the failing step began
  const int extensor = model.id(mjOBJ_TENDON, "extensor");

  const Data raw = make_data(model);
  raw->qpos[model->jnt_qposadr[model.id(mjOBJ_JOINT, "wrist_fe")]] = kFe;
  raw->qpos[model->jnt_qposadr[model.id(mjOBJ_JOINT, "wrist_ur")]] = kUr;
  mj_forward(model.get(), raw.get());
  ASSERT_TRUE(std::isnan(raw->ten_length[extensor])) << "MuJoCo no longer fails here: the fixture tests nothing";

  WristSim wrist(model);
  wrist.set_pose(kFe, kUr, {0.0, 0.0, 137.0, 0.0});
  const double length = wrist.data()->ten_length[extensor];
  ASSERT_TRUE(std::isfinite(length));
  // Grazing, the path is the straight line between its two sites (an arc of zero).
  const mjtNum* forearm = wrist.data()->site_xpos + 3 * model.id(mjOBJ_SITE, "extensor_forearm");
  const mjtNum* hand = wrist.data()->site_xpos + 3 * model.id(mjOBJ_SITE, "extensor_hand");
  EXPECT_NEAR(length, std::hypot(hand[0] - forearm[0], hand[1] - forearm[1], hand[2] - forearm[2]), 1e-9);
  EXPECT_TRUE(std::isfinite(wrist.muscle_torque(kExtensor)));
  // The wrist was all but still there: it steps on and stays.
  EXPECT_NO_THROW(wrist.run(0.5));
  EXPECT_NEAR(wrist.angle(physics::WristAxis::kUlnarRadial), kUr, 0.01);
}

// Each field set to something no device has: refused by parse_device (before any model is built), the message
// naming the file and the field.
TEST(ModelRobustness, InvalidDeviceIsRefusedNamingTheField) {
  const nlohmann::json valid = nlohmann::json::parse(device_to_json(paper_device()));
  struct Case {
    std::string pointer;  // JSON pointer of the field
    nlohmann::json value;
    std::string named;  // what the message must name
  };
  const std::vector<Case> cases = {
      {"/muscles/flexor/d1_cm", -3.0, "muscles.flexor"},
      {"/muscles/flexor/L0_cm", 0.0, "muscles.flexor"},
      {"/muscles/ulnar/rw_cm", "two", "muscles.ulnar.rw_cm"},
      {"/muscles/radial/w2_cm", nullptr, "muscles.radial.w2_cm"},
      {"/fpam/table/1/eps_max", 0.9, "fpam.table"},
      {"/fpam/table/2/r0_cm", -1.0, "fpam.table"},
      {"/stretch/mode", "elastic", "stretch.mode"},
      {"/stretch/K1_n_per_cm2", 0.0, "stretch"},
      {"/regulator/max_pressure_kpa", -137.0, "regulator.max_pressure_kpa"},
      {"/regulator/time_constant_s", 0.0, "regulator.time_constant_s"},
      {"/wrist/damping_fe_nms_per_rad", -0.1, "wrist.damping_fe_nms_per_rad"},
      {"/wrist/flexion_limit_deg", 0.0, "wrist.flexion_limit_deg"},
      {"/hand/mass_kg", -0.45, "hand.mass_kg"},
      {"/hand/length_cm", "long", "hand.length_cm"},
      {"/muscles/flexor/d1_cmm", 19.0, "muscles.flexor.d1_cmm"},  // a misspelt key
  };
  for (const Case& c : cases) {
    nlohmann::json broken = valid;
    broken[nlohmann::json::json_pointer(c.pointer)] = c.value;
    try {
      parse_device(broken.dump(), "user.json");
      ADD_FAILURE() << c.pointer << " = " << c.value.dump() << " was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_THAT(e.what(), HasSubstr("user.json: " + c.named)) << c.pointer;
    }
  }
}

}  // namespace
}  // namespace softwrist::sim
