// The MuJoCo model with the fPAM plugin, checked against the physics core's 2D model.

#include "sim/model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "physics/fpam_force.h"
#include "physics/fpam_hysteresis.h"
#include "physics/muscle_torque.h"
#include "physics/pressure_regulator.h"
#include "physics/units.h"
#include "sim/device.h"
#include "sim/model_builder.h"
#include "sim/wrist_sim.h"
#include "sim/wrist_statics.h"

namespace softwrist::sim {
namespace {

using units::deg_to_rad;

const PluginSet& plugins() {
  static const PluginSet set = PluginSet::Default();
  return set;
}

struct Sim {
  explicit Sim(const DeviceDescription& device)
      : model(Model::FromXml(build_model_xml(device), plugins())), data(make_data(model)) {
    fe = model->jnt_dofadr[model.id(mjOBJ_JOINT, "wrist_fe")];
    ur = model->jnt_dofadr[model.id(mjOBJ_JOINT, "wrist_ur")];
  }
  // Holds the wrist at (fe, ur) with the given regulated pressures [kPa] and evaluates the model.
  void hold(double fe_angle, double ur_angle, const std::array<double, 4>& kpa) {
    mj_resetData(model.get(), data.get());
    data->qpos[model->jnt_qposadr[model.id(mjOBJ_JOINT, "wrist_fe")]] = fe_angle;
    data->qpos[model->jnt_qposadr[model.id(mjOBJ_JOINT, "wrist_ur")]] = ur_angle;
    for (int i = 0; i < 4; ++i) data->act[i] = kpa[static_cast<std::size_t>(i)];
    mj_forward(model.get(), data.get());
  }
  // Joint torque of one actuator on one dof: its force times its moment (its share of qfrc_actuator).
  double torque(int actuator, int dof) const {
    return data->actuator_force[actuator] * data->actuator_moment[actuator * model->nv + dof];
  }
  Model model;
  Data data;
  int fe = -1, ur = -1;
};

// The cross-check: the flexor held at the paper's eight angles and a 1-degree grid, at the five pressures,
// straight and wrapping, with and without stretching: MuJoCo's joint torque equals the 2D model within 2 % or
// 0.02 Nm. In its own plane the spatial tendon wrapping a cylinder about the joint axis is exactly the 2D geometry,
// so the tendon length is checked to 1e-9 m as well.
TEST(ModelCrossCheck, FlexorTorqueMatchesThe2DModel) {
  for (auto mode : {physics::StretchMode::kNone, physics::StretchMode::kSelfConsistent}) {
    DeviceDescription device = paper_device();
    device.stretch_mode = mode;
    Sim sim(device);
    const physics::Muscle flexor = device.muscle(kFlexor);
    std::vector<double> angles_deg = {-67.5, -45.0, -22.5, 0.0, 22.5, 45.0, 67.5, 90.0};
    for (int a = -67; a <= 90; ++a) angles_deg.push_back(a);
    int wrapped = 0, straight = 0;
    for (const double deg : angles_deg) {
      for (const double kpa : {0.0, 34.0, 68.0, 103.0, 137.0}) {
        sim.hold(deg_to_rad(deg), 0.0, {kpa, 0.0, 0.0, 0.0});
        const auto expected = physics::muscle_state(flexor, deg_to_rad(deg), kpa * 1e3);
        ASSERT_NEAR(sim.data->actuator_length[kFlexor], expected.path_length, 1e-9) << deg;
        const double torque = sim.torque(kFlexor, sim.fe);
        ASSERT_NEAR(torque, expected.torque, std::max(0.02, 0.02 * std::abs(expected.torque)))
            << physics::to_string(mode) << " " << deg << " deg " << kpa << " kPa";
        (expected.regime == physics::Regime::kWrapping ? wrapped : straight) += 1;
      }
    }
    EXPECT_GT(wrapped, 100);
    EXPECT_GT(straight, 100);
  }
}

// One muscle in its own plane (the extensor sees -fe, the ulnar muscle +ur, the radial -ur) held at 103 kPa from
// `from_deg` to `to_deg`: MuJoCo's tendon length equals the 2D path to 1e-9 m and its joint torque the 2D model's
// within 2 % or 0.02 N m. Counts the angles in each regime into `wrapped` and `straight`.
struct PlaneCase {
  int muscle, dof_sign;
  bool fe_plane;
};
constexpr std::array<PlaneCase, 4> kPlanes = {
    {{kFlexor, 1, true}, {kExtensor, -1, true}, {kUlnar, 1, false}, {kRadial, -1, false}}};

void expect_matches_in_its_plane(Sim& sim, const DeviceDescription& device, const PlaneCase& c, int from_deg,
                                 int to_deg, int step_deg, int& wrapped, int& straight) {
  const physics::Muscle muscle = device.muscle(c.muscle);
  for (int deg = from_deg; deg <= to_deg; deg += step_deg) {
    std::array<double, 4> kpa{};
    kpa[static_cast<std::size_t>(c.muscle)] = 103.0;
    const double q = deg_to_rad(deg);
    sim.hold(c.fe_plane ? q : 0.0, c.fe_plane ? 0.0 : q, kpa);
    const auto expected = physics::muscle_state(muscle, c.dof_sign * q, 103e3);
    ASSERT_NEAR(sim.data->actuator_length[c.muscle], expected.path_length, 1e-9) << c.muscle << " " << deg;
    const double torque = c.dof_sign * sim.torque(c.muscle, c.fe_plane ? sim.fe : sim.ur);
    ASSERT_NEAR(torque, expected.torque, std::max(0.02, 0.02 * std::abs(expected.torque))) << c.muscle << " " << deg;
    (expected.regime == physics::Regime::kWrapping ? wrapped : straight) += 1;
  }
}

// The other three muscles in their own planes.
TEST(ModelCrossCheck, EveryMuscleMatchesThe2DModelInItsPlane) {
  const DeviceDescription device = paper_device();
  Sim sim(device);
  int wrapped = 0, straight = 0;
  for (std::size_t k = 1; k < kPlanes.size(); ++k)
    expect_matches_in_its_plane(sim, device, kPlanes[k], -50, 50, 5, wrapped, straight);
}

// The wrist circle's centre off the joint (physics::WrapSurface): the generated model moves each wrap cylinder with it,
// fixed to the forearm as the 2D law has it, and the two agree as at the joint, in both regimes, for all four muscles.
TEST(ModelCrossCheck, EveryMuscleMatchesThe2DModelWithTheWrapCentreOffTheJoint) {
  DeviceDescription device = paper_device();
  const std::array<physics::WrapSurface, 4> centres = {
      {{.x = 0.006, .y = 0.004}, {.x = 0.006, .y = -0.004}, {.x = -0.003, .y = 0.005}, {.x = -0.003, .y = -0.005}}};
  for (std::size_t i = 0; i < 4; ++i) device.muscles[i].wrap_surface = centres[i];
  Sim sim(device);
  int wrapped = 0, straight = 0;
  for (const PlaneCase& c : kPlanes) expect_matches_in_its_plane(sim, device, c, -60, 60, 4, wrapped, straight);
  EXPECT_GT(wrapped, 20);
  EXPECT_GT(straight, 20);
}

// A wrist surface that is not a circle (physics::WrapSurface aspect): MuJoCo wraps only cylinders, so the wrap cylinder
// stands for the surface's equivalent circle, which WristSim moves before every evaluation (model_builder.h). In each
// muscle's plane the tendon length equals the 2D path on the ellipse to 1e-9 m and the torque the 2D model's within
// 2 %, in both regimes, for all four muscles; the shared model is not touched (WristSim moves its own copy).
TEST(ModelCrossCheck, EveryMuscleMatchesThe2DModelOnANonCircularWrist) {
  DeviceDescription device = paper_device();
  const std::array<physics::WrapSurface, 4> surfaces = {{{.aspect = 1.4},
                                                         {.x = 0.003, .y = -0.002, .aspect = 0.75},
                                                         {.aspect = 1.25},
                                                         {.x = -0.002, .y = 0.003, .aspect = 1.6}}};
  for (std::size_t i = 0; i < 4; ++i) device.muscles[i].wrap_surface = surfaces[i];
  const Model model = Model::FromXml(build_model_xml(device), plugins());
  const std::vector<double> sizes(model->geom_size, model->geom_size + 3 * model->ngeom);
  WristSim wrist(model);
  int wrapped = 0, straight = 0;
  for (const PlaneCase& c : kPlanes) {
    const physics::Muscle muscle = device.muscle(c.muscle);
    for (int deg = -60; deg <= 60; deg += 4) {
      std::array<double, 4> kpa{};
      kpa[static_cast<std::size_t>(c.muscle)] = 103.0;
      const double q = deg_to_rad(deg);
      wrist.set_pose(c.fe_plane ? q : 0.0, c.fe_plane ? 0.0 : q, kpa);
      const auto expected = physics::muscle_state(muscle, c.dof_sign * q, 103e3);
      ASSERT_NEAR(wrist.data()->actuator_length[c.muscle], expected.path_length, 1e-9) << c.muscle << " " << deg;
      const double torque = wrist.muscle_torque(static_cast<MuscleIndex>(c.muscle));
      ASSERT_NEAR(torque, expected.torque, std::max(0.02, 0.02 * std::abs(expected.torque))) << c.muscle << " " << deg;
      (expected.regime == physics::Regime::kWrapping ? wrapped : straight) += 1;
    }
  }
  EXPECT_GT(wrapped, 20);
  EXPECT_GT(straight, 20);
  EXPECT_NE(wrist.model(), model.get());
  EXPECT_EQ(std::vector<double>(model->geom_size, model->geom_size + 3 * model->ngeom), sizes);
  // Free motion stays finite with the surfaces moving every step.
  wrist.reset();
  wrist.command_pressures_kpa({137.0, 0.0, 80.0, 0.0});
  wrist.run(1.0);
  EXPECT_GT(wrist.angle(physics::WristAxis::kFlexionExtension), deg_to_rad(5.0));
}

// Regulator: a step in commanded pressure reaches 63 % at the time constant; the pressure never leaves [0, max].
// Routing (device.h): planar, every muscle is the paper's 2D model on its own joint whatever the other joint's angle
// (and moves only its own); spatial, MuJoCo's tendon agrees with it at the other joint's zero and not away from it:
// there a flexor, its mounts off the deviation axis, also deviates the hand, and an ulnar muscle's moment arm about
// its (turned) joint shrinks.
TEST(ModelCrossCheck, PlanarRoutingIsThe2DModelOnItsOwnJointAlone) {
  DeviceDescription device = rom_device();
  device.stretch_mode = physics::StretchMode::kSelfConsistent;
  DeviceDescription planar_device = device;
  planar_device.routing = Routing::kPlanar;
  Sim spatial(device), planar(planar_device);
  const std::array<double, 4> kpa{60.0, 60.0, 60.0, 60.0};
  double spatial_cross = 0.0, spatial_own_error = 0.0;
  for (const double other_deg : {0.0, -25.0, 30.0}) {
    for (const double own_deg : {-15.0, 0.0, 12.0}) {
      for (int m = 0; m < 4; ++m) {
        const auto muscle = static_cast<MuscleIndex>(m);
        const bool fe_muscle = physics::axis_of(muscle) == physics::WristAxis::kFlexionExtension;
        const double direction = physics::direction_of(muscle);
        const double own = deg_to_rad(own_deg), other = deg_to_rad(other_deg);
        const double fe = fe_muscle ? direction * own : other, ur = fe_muscle ? other : direction * own;
        const auto expected = physics::muscle_state(device.muscle(m), own, 60.0e3);
        for (Sim* sim : {&spatial, &planar}) {
          sim->hold(fe, ur, kpa);
          const double own_torque = direction * sim->torque(m, fe_muscle ? sim->fe : sim->ur);
          const double cross_torque = sim->torque(m, fe_muscle ? sim->ur : sim->fe);
          if (sim == &planar) {
            EXPECT_NEAR(own_torque, expected.torque, 1e-9) << m << " " << own_deg << " " << other_deg;
            EXPECT_EQ(cross_torque, 0.0);
          } else if (other_deg == 0.0) {
            EXPECT_NEAR(own_torque, expected.torque, std::max(0.02, 0.02 * std::abs(expected.torque)));
          } else {
            spatial_cross = std::max(spatial_cross, std::abs(cross_torque));
            spatial_own_error = std::max(spatial_own_error, std::abs(own_torque - expected.torque));
          }
        }
      }
    }
  }
  EXPECT_GT(spatial_cross, 0.02);      // [N m] the spatial tendons' coupling this test documents
  EXPECT_GT(spatial_own_error, 0.02);  // [N m]
}

TEST(ModelRegulator, StepReaches63PercentAtTheTimeConstantAndStaysInRange) {
  DeviceDescription device = paper_device();
  Sim sim(device);
  mj_resetData(sim.model.get(), sim.data.get());
  const double tau = device.regulator.time_constant;
  sim.data->ctrl[kFlexor] = 100.0;
  while (sim.data->time < tau - 1e-12) mj_step(sim.model.get(), sim.data.get());
  EXPECT_NEAR(sim.data->act[kFlexor] / 100.0, 1.0 - std::exp(-1.0), 0.01);
  // Commands outside the regulator's range: the pressure stays within [0, 137] kPa.
  mj_resetData(sim.model.get(), sim.data.get());
  double low = 1e9, high = -1e9;
  for (int step = 0; step < 3000; ++step) {
    sim.data->ctrl[kFlexor] = step < 1500 ? 500.0 : -50.0;
    sim.data->ctrl[kUlnar] = 1e6;
    mj_step(sim.model.get(), sim.data.get());
    for (int i = 0; i < 4; ++i) {
      low = std::min(low, sim.data->act[i]);
      high = std::max(high, sim.data->act[i]);
    }
  }
  EXPECT_GE(low, 0.0);
  EXPECT_LE(high, 137.0 + 1e-9);
  EXPECT_GT(high, 136.0);
}

// A second-order regulator (physics/pressure_regulator.h, tau2 = 0.08 s against tau = 0.1 s: damping ratio 0.625):
// the pressure and its rate, kept in the muscle's companion actuator, are the physics core's exact steps, and the
// pressure overshoots the command as such a regulator does.
TEST(ModelRegulator, SecondOrderPressureIsThePhysicsCoresAndOvershoots) {
  DeviceDescription device = paper_device();
  device.regulator.second_order_time = 0.08;
  Sim sim(device);
  ASSERT_EQ(sim.model->nu, 8) << "four fPAMs and their four pressure rates";
  const int rate = sim.model.id(mjOBJ_ACTUATOR, "flexor_pressure_rate");
  mj_resetData(sim.model.get(), sim.data.get());
  physics::RegulatedPressure expected;
  double peak = 0.0;
  for (int step = 0; step < 500; ++step) {
    sim.data->ctrl[kFlexor] = 100.0;
    mj_step(sim.model.get(), sim.data.get());
    expected = physics::regulator_step(device.regulator.response(), expected, 100.0, sim.model->opt.timestep);
    ASSERT_NEAR(sim.data->act[kFlexor], expected.pressure, 1e-9) << step;
    ASSERT_NEAR(sim.data->act[rate], expected.rate, 1e-7) << step;
    EXPECT_EQ(sim.data->actuator_force[rate], 0.0) << "a companion pulls nothing";
    peak = std::max(peak, sim.data->act[kFlexor]);
  }
  EXPECT_GT(peak, 105.0);
}

// Free motion: each muscle alone at 137 kPa moves the relaxed wrist in its own direction and it settles there.
TEST(ModelFreeMotion, EachMuscleAloneSettlesInItsOwnDirection) {
  Sim sim(paper_device());
  const std::array<std::pair<int, double>, 4> expected_sign = {
      {{kFlexor, 1.0}, {kExtensor, -1.0}, {kUlnar, 1.0}, {kRadial, -1.0}}};
  for (const auto& [muscle, sign] : expected_sign) {
    mj_resetData(sim.model.get(), sim.data.get());
    sim.data->ctrl[muscle] = 137.0;
    for (int step = 0; step < 6000; ++step) mj_step(sim.model.get(), sim.data.get());
    const int dof = (muscle == kFlexor || muscle == kExtensor) ? sim.fe : sim.ur;
    const double angle = sim.data->qpos[dof];
    EXPECT_GT(sign * angle, deg_to_rad(5.0)) << kMuscleNames[static_cast<std::size_t>(muscle)];
    EXPECT_LT(std::abs(sim.data->qvel[dof]), 1e-2) << "settled";
  }
}

// Each muscle alone at 137 kPa for 6 s in MuJoCo, the hand supported: its angle in its own direction [rad].
double settled_in_mujoco(const DeviceDescription& device, MuscleIndex muscle) {
  const Model model = Model::FromXml(build_model_xml(device, {.gravity = 0.0}), plugins());
  WristSim wrist(model);
  std::array<double, 4> command{};
  command[static_cast<std::size_t>(muscle)] = 137.0;
  wrist.command_pressures_kpa(command);
  wrist.run(6.0);
  return physics::direction_of(muscle) * wrist.angle(physics::axis_of(muscle));
}

// For each muscle, how much less far the device `changed(muscle)` lets it settle than the paper's, in MuJoCo and in the
// statics of the same law (sim::settled_angle): they agree within 0.5 deg. Returns the largest change in the statics.
double expect_settling_as_the_statics(const std::function<DeviceDescription(MuscleIndex)>& changed) {
  double largest = 0.0;
  for (int m = 0; m < 4; ++m) {
    const auto muscle = static_cast<MuscleIndex>(m);
    const DeviceDescription device = changed(muscle);
    const double kpa = units::kpa_to_pa(137.0);
    const double statics =
        std::abs(settled_angle(paper_device(), muscle, kpa, 0.0)) - std::abs(settled_angle(device, muscle, kpa, 0.0));
    const double mujoco = settled_in_mujoco(paper_device(), muscle) - settled_in_mujoco(device, muscle);
    EXPECT_NEAR(mujoco, statics, deg_to_rad(0.5)) << kMuscleNames[static_cast<std::size_t>(m)];
    largest = std::max(largest, std::abs(statics));
  }
  return largest;
}

// The relaxed wrist's stiffening towards its limits (physics/relaxed_wrist.h), applied by WristSim, holds each muscle's
// settled angle back by as much in MuJoCo as in the statics of the same law: the MuJoCo model and the analytic one
// agree on the nonlinear wrist as on the linear one. The hand is supported: its sag about the other axis would couple
// the axes through the 3D tendon paths, which the per-axis statics leave out.
TEST(ModelFreeMotion, LimitStiffeningHoldsTheWristBackAsTheStaticsSay) {
  DeviceDescription stiff = paper_device();
  stiff.wrist.limit_stiffening = {.torque = 2.0, .angle_scale = deg_to_rad(8.0)};
  EXPECT_GT(expect_settling_as_the_statics([&](MuscleIndex) { return stiff; }), deg_to_rad(2.0));
}

// A relaxed wrist stiffer towards extension than flexion, or towards ulnar than radial deviation (PassiveWrist's
// asymmetry, applied by WristSim about MuJoCo's symmetric joint stiffness), holds each muscle's settled angle back, or
// lets it further, by as much in MuJoCo as in the statics of the same law (the flexor and the radial muscle pull
// towards their axes' stiffer sides, 1.5 k and 1.4 k, the other two towards the softer). Each muscle with the asymmetry
// of its own axis only: a muscle's pull turns the hand a little about the other axis too (the 3D paths), which a
// stiffness asymmetric there would resist differently, and the per-axis statics leave that coupling out.
TEST(ModelFreeMotion, AnAsymmetricWristSettlesAsTheStaticsSay) {
  EXPECT_GT(expect_settling_as_the_statics([](MuscleIndex muscle) {
              DeviceDescription asymmetric = paper_device();
              (physics::axis_of(muscle) == physics::WristAxis::kFlexionExtension
                   ? asymmetric.wrist.stiffness_asymmetry_fe
                   : asymmetric.wrist.stiffness_asymmetry_ur) = std::array{0.5, 0.4, -0.5, -0.4}[muscle];
              return asymmetric;
            }),
            deg_to_rad(2.0));
}

// The fabric's hysteresis as a state of the plugin's force (physics/fpam_hysteresis.h): the flexor at 137 kPa is moved
// to the same angle from either side at a prescribed speed; MuJoCo's branch state is Dahl's closed form of the tendon's
// length change, s = +-(1 - exp(-|dL| / l_h)), and its force the static law's (the same model without hysteresis, the
// paper's Eqn. force with the mounts' stretch) plus s (h F + F_0 + mu pi r0^2 P), for a loop that scales with the pull
// and for a dry friction that grows with pressure: the pull after lengthening exceeds the pull after shortening at
// the same length.
class HysteresisCrossCheck : public testing::TestWithParam<physics::FpamHysteresis> {};

TEST_P(HysteresisCrossCheck, StateIsDahlsAndForceIsTheStaticLawsPlusTheLoop) {
  DeviceDescription device = paper_device();
  device.hysteresis = GetParam();
  const double pressure = units::kpa_to_pa(137.0);
  const double end_force = physics::pressure_end_force(pressure, device.fpam.at_pressure(pressure));
  Sim sim(device);
  ASSERT_EQ(sim.model->nu, 8) << "four fPAMs and their four hysteresis states";
  Sim static_sim(paper_device());
  const double target = deg_to_rad(10.0);
  static_sim.hold(target, 0.0, {137.0, 0.0, 0.0, 0.0});
  const double static_force = static_sim.data->actuator_force[kFlexor];
  const int fe_qpos = sim.model->jnt_qposadr[sim.model.id(mjOBJ_JOINT, "wrist_fe")];
  const int ur_qpos = sim.model->jnt_qposadr[sim.model.id(mjOBJ_JOINT, "wrist_ur")];
  double after_lengthening = 0.0, after_shortening = 0.0;
  for (const double start_deg : {-20.0, 40.0}) {
    sim.hold(deg_to_rad(start_deg), 0.0, {137.0, 0.0, 0.0, 0.0});
    const double start_length = sim.data->actuator_length[kFlexor];
    const double duration = 0.5, speed = (target - deg_to_rad(start_deg)) / duration;
    sim.data->ctrl[kFlexor] = 137.0;
    while (sim.data->time < duration - 1e-9) {  // prescribed motion: the branch integrates the tendon's velocity
      sim.data->qpos[fe_qpos] = deg_to_rad(start_deg) + speed * sim.data->time;
      sim.data->qvel[sim.fe] = speed;
      sim.data->qpos[ur_qpos] = sim.data->qvel[sim.ur] = 0.0;  // the other axis held
      mj_step(sim.model.get(), sim.data.get());
    }
    sim.data->qpos[fe_qpos] = target;
    sim.data->qpos[ur_qpos] = sim.data->qvel[sim.fe] = sim.data->qvel[sim.ur] = 0.0;
    mj_forward(sim.model.get(), sim.data.get());
    const double change = sim.data->actuator_length[kFlexor] - start_length;
    const double branch = sim.data->act[4 + kFlexor];
    const double expected_branch = (change > 0.0 ? 1.0 : -1.0) * (1.0 - std::exp(-std::abs(change) / 0.002));
    EXPECT_NEAR(branch, expected_branch, 0.01) << "from " << start_deg << " deg, dL " << change;
    const double expected = std::copysign(
        physics::hysteretic_force(device.hysteresis, std::abs(static_force), branch, end_force), static_force);
    EXPECT_NEAR(sim.data->actuator_force[kFlexor], expected, 1e-9 * std::abs(static_force));
    EXPECT_EQ(sim.data->actuator_force[4 + kFlexor], 0.0) << "a state pulls nothing";
    (change > 0.0 ? after_lengthening : after_shortening) = std::abs(sim.data->actuator_force[kFlexor]);
  }
  EXPECT_GT(after_lengthening, 1.15 * after_shortening);  // s near 1 over centimetres
}

INSTANTIATE_TEST_SUITE_P(ModelCrossCheck, HysteresisCrossCheck,
                         testing::Values(physics::FpamHysteresis{.fraction = 0.2, .transition_length = 0.002},
                                         physics::FpamHysteresis{.friction_force = 1.0,
                                                                 .pressure_friction = 0.05,
                                                                 .transition_length = 0.002}));

// Every combination of 0 and 137 kPa on the four muscles stays finite.
TEST(ModelFreeMotion, FiniteAtEveryCornerOfThePressureGrid) {
  Sim sim(paper_device());
  for (int corner = 0; corner < 16; ++corner) {
    mj_resetData(sim.model.get(), sim.data.get());
    for (int i = 0; i < 4; ++i) sim.data->ctrl[i] = (corner >> i) & 1 ? 137.0 : 0.0;
    for (int step = 0; step < 2000; ++step) mj_step(sim.model.get(), sim.data.get());
    for (int i = 0; i < sim.model->nq; ++i) ASSERT_TRUE(std::isfinite(sim.data->qpos[i])) << corner;
    for (int i = 0; i < sim.model->nu; ++i) ASSERT_TRUE(std::isfinite(sim.data->actuator_force[i])) << corner;
  }
}

// The model sizes mjData for its only constraint rows (model_builder.cc's <size>): the two joints' limits, and friction
// loss on the four tendons where the diagnosis's synthetic device adds it (with_tendon_friction). Pushed
// past both limits at once, every muscle at full pressure, every row acts and nothing is dropped or overflows.
TEST(ModelFreeMotion, BothJointLimitsAndTendonFrictionFitTheConstraintSpace) {
  for (const bool tendon_friction : {false, true}) {
    const std::string plain = build_model_xml(paper_device());
    const Model model = Model::FromXml(tendon_friction ? with_tendon_friction(plain, 3.0) : plain, plugins());
    const Data data = make_data(model);
    for (const double sign : {-1.0, 1.0}) {
      mj_resetData(model.get(), data.get());
      for (int j = 0; j < model->njnt; ++j) {
        const double past = sign > 0 ? model->jnt_range[2 * j + 1] + 0.05 : model->jnt_range[2 * j] - 0.05;
        data->qpos[model->jnt_qposadr[j]] = past;
      }
      for (int i = 0; i < 4; ++i) data->ctrl[i] = 137.0;
      mj_forward(model.get(), data.get());
      EXPECT_EQ(data->nefc, tendon_friction ? 6 : 2) << sign;
      for (int step = 0; step < 500; ++step) mj_step(model.get(), data.get());
      for (const int warning : {mjWARN_CNSTRFULL, mjWARN_CONTACTFULL, mjWARN_BADQACC})
        EXPECT_EQ(data->warning[warning].number, 0) << "warning " << warning << ", sign " << sign;
      for (int i = 0; i < model->nq; ++i) EXPECT_TRUE(std::isfinite(data->qpos[i])) << sign;
    }
  }
}

// Threads stepping different mjData of the same model, and of a second model, give exactly the sequential result:
// the plugin's instances are immutable and its per-step state lives in mjData.
TEST(ModelThreads, ConcurrentSteppingMatchesSequential) {
  DeviceDescription other = paper_device();
  other.stretch_mode = physics::StretchMode::kOneShot;
  const Model a = Model::FromXml(build_model_xml(paper_device()), plugins());
  const Model b = Model::FromXml(build_model_xml(other), plugins());
  auto run = [](const Model& model, double kpa) {
    Data data = make_data(model);
    for (int step = 0; step < 3000; ++step) {
      data->ctrl[kFlexor] = (step / 500) % 2 ? kpa : 10.0;
      data->ctrl[kExtensor] = (step / 500) % 2 ? 10.0 : kpa;
      mj_step(model.get(), data.get());
    }
    return std::array<double, 2>{data->qpos[0], data->qpos[1]};
  };
  const auto expected_a = run(a, 120.0), expected_b = run(b, 90.0);
  std::array<std::array<double, 2>, 4> results{};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] { results[static_cast<std::size_t>(t)] = t % 2 ? run(b, 90.0) : run(a, 120.0); });
  }
  for (auto& thread : threads) thread.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(results[static_cast<std::size_t>(t)], t % 2 ? expected_b : expected_a) << t;
  EXPECT_NE(expected_a, expected_b);
}

TEST(ModelLoad, FromFileLoadsTheShippedModelAndNamesAMissingFile) {
  const Model model = Model::FromFile(std::string(SOFTWRIST_SOURCE_DIR) + "/models/paper_device.xml", plugins());
  EXPECT_EQ(model->nu, 4);
  try {
    Model::FromFile("/nonexistent/wrist.xml", plugins());
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/wrist.xml: cannot open"), std::string::npos) << e.what();
  }
}

// The generated model gives the fPAMs a fixed gain of 0 (MuJoCo calls no gain hook); an MJCF written with gaintype
// "user" (docs/plugin-fpam.md's first form, whose hook returns 0) loads and moves bit for bit the same, hysteresis
// states included.
TEST(ModelLoad, UserGainAndFixedZeroGainMoveTheSame) {
  DeviceDescription device = paper_device();
  device.hysteresis.fraction = 0.1;
  const std::string fixed = build_model_xml(device);
  std::string user = fixed;
  for (auto at = user.find("gaintype=\"fixed\" gainprm=\"0\""); at != std::string::npos;
       at = user.find("gaintype=\"fixed\" gainprm=\"0\"", at))
    user.replace(at, 28, "gaintype=\"user\"");
  ASSERT_NE(user, fixed);
  std::vector<std::vector<double>> runs;
  for (const std::string& xml : {fixed, user}) {
    const Model model = Model::FromXml(xml, plugins());
    WristSim wrist(model);
    wrist.command_pressures_kpa({120.0, 10.0, 70.0, 0.0});
    wrist.run(0.5);
    runs.push_back({wrist.angle(physics::WristAxis::kFlexionExtension), wrist.angle(physics::WristAxis::kUlnarRadial)});
  }
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_GT(std::abs(runs[0][0]), 0.05);
}

// A malformed model or plugin configuration fails at load, naming the actuator and the attribute.
TEST(ModelLoad, MalformedConfigurationsFailAtLoadNamingTheProblem) {
  // `model` with its first `from` replaced by `to`.
  const auto replaced_in = [](std::string model, const std::string& from, const std::string& to) {
    const auto at = model.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return model.replace(at, from.size(), to);
  };
  const std::string xml = build_model_xml(paper_device());
  auto replaced = [&](const std::string& from, const std::string& to) { return replaced_in(xml, from, to); };
  std::vector<std::pair<std::string, std::string>> cases = {
      {replaced("softwrist.fpam rest_length=0.32 ", "softwrist.fpam "),
       "actuator 'flexor': attribute 'rest_length': missing"},
      {replaced("softwrist.fpam rest_length=0.32 ", "softwrist.fpam rest_length=-1 "),
       "actuator 'flexor': attribute 'rest_length'"},
      {replaced("table_eps_max=0.153", "table_eps_max=1.5"), "actuator 'flexor'"},
      {replaced("data=\"softwrist.fpam rest_length=0.32", "data=\"acme.muscle rest_length=0.32"),
       "actuator 'flexor': unknown plugin 'acme.muscle'"},
      {replaced("<text name=\"plugin:flexor\"", "<text name=\"plugin:nobody\""), "actuator 'flexor' has user"},
      {replaced("<tendon>", "<tendon><bogus/>"), "model.xml"},
      {replaced("gainprm=\"0\"", "gainprm=\"2\""),
       "actuator 'flexor': softwrist.fpam needs dyntype and biastype 'user', and gaintype 'user' or 'fixed' with "
       "gainprm 0"},
      {"<mujoco><worldbody>", "model.xml"},
  };
  // With hysteresis: a state's actuator that is missing, or that acts on another muscle's tendon.
  DeviceDescription hysteretic = paper_device();
  hysteretic.hysteresis.fraction = 0.1;
  const std::string with_states = build_model_xml(hysteretic);
  auto state_replaced = [&](const std::string& from, const std::string& to) {
    return replaced_in(with_states, from, to);
  };
  cases.push_back({state_replaced("    <general name=\"flexor_hysteresis\" tendon=\"flexor\" dyntype=\"user\" "
                                  "gaintype=\"fixed\" gainprm=\"0\" biastype=\"user\" actlimited=\"true\" "
                                  "actrange=\"-1 1\"/>\n",
                                  ""),
                   "actuator 'flexor': has hysteresis but no actuator 'flexor_hysteresis'"});
  cases.push_back(
      {state_replaced("name=\"flexor_hysteresis\" tendon=\"flexor\"", "name=\"flexor_hysteresis\" tendon=\"extensor\""),
       "actuator 'flexor_hysteresis': must act on the same tendon (or joint, with the same gear) as 'flexor'"});
  // The transmission its routing reads: a tendon's length (spatial), its own hinge's angle with gear +-1 (planar).
  cases.push_back(
      {replaced("<general name=\"flexor\" tendon=\"flexor\"", "<general name=\"flexor\" joint=\"wrist_fe\""),
       "actuator 'flexor': routing=spatial needs a tendon transmission"});
  DeviceDescription planar = hysteretic;
  planar.routing = Routing::kPlanar;
  const std::string planar_xml = build_model_xml(planar);
  auto planar_replaced = [&](const std::string& from, const std::string& to) {
    return replaced_in(planar_xml, from, to);
  };
  cases.push_back({planar_replaced("name=\"radial\" joint=\"wrist_ur\" gear=\"-1\"",
                                   "name=\"radial\" joint=\"wrist_ur\" gear=\"-2\""),
                   "actuator 'radial': routing=planar needs gear +1 or -1"});
  cases.push_back({planar_replaced("name=\"ulnar_hysteresis\" joint=\"wrist_ur\" gear=\"1\"",
                                   "name=\"ulnar_hysteresis\" joint=\"wrist_ur\" gear=\"-1\""),
                   "actuator 'ulnar_hysteresis': must act on the same tendon (or joint, with the same gear)"});
  cases.push_back({planar_replaced("name=\"flexor\" joint=\"wrist_fe\"", "name=\"flexor\" tendon=\"flexor\""),
                   "actuator 'flexor': routing=planar needs a hinge joint transmission"});
  // A second-order regulator without its pressure's rate.
  DeviceDescription second_order = paper_device();
  second_order.regulator.second_order_time = 0.03;
  std::string with_rates = build_model_xml(second_order);
  const std::string rate_actuator =
      "    <general name=\"radial_pressure_rate\" tendon=\"radial\" dyntype=\"user\" gaintype=\"fixed\" "
      "gainprm=\"0\" biastype=\"user\"/>\n";
  const auto rate_at = with_rates.find(rate_actuator);
  EXPECT_NE(rate_at, std::string::npos);
  if (rate_at != std::string::npos) with_rates.erase(rate_at, rate_actuator.size());
  cases.push_back(
      {with_rates, "actuator 'radial': has a second-order regulator but no actuator 'radial_pressure_rate'"});
  std::string rk4 = build_model_xml(second_order);
  const auto option_at = rk4.find("<option ");
  EXPECT_NE(option_at, std::string::npos);
  if (option_at != std::string::npos) rk4.insert(option_at + 8, "integrator=\"RK4\" ");
  cases.push_back({rk4, "actuator 'flexor': a second-order regulator needs the Euler integrator, not RK4"});
  for (const auto& [text, expected] : cases) {
    try {
      Model::FromXml(text, plugins());
      ADD_FAILURE() << "loaded a model that should fail with: " << expected;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace softwrist::sim
