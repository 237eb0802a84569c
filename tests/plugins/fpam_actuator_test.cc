#include "fpam_actuator.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <gtest/gtest.h>

#include "physics/muscle_torque.h"
#include "physics/paper_parameters.h"
#include "physics/pressure_regulator.h"
#include "physics/torque_geometry.h"

namespace softwrist::plugin {
namespace {

std::optional<FpamActuator> create(const std::string& text, std::string* error) {
  std::string parse_error;
  const auto config = PluginConfig::Parse(text, &parse_error);
  if (!config) {
    *error = parse_error;
    return std::nullopt;
  }
  return FpamActuator::Create(*config, "flexor", error);
}

const char* kTorqueRig =
    "softwrist.fpam rest_length=0.32 table_pressure_kpa=0,34,68,103,137 table_r0=0.0123,0.0127,0.0122,0.0119,0.0126 "
    "table_eps_max=0.153,0.303,0.296,0.301,0.277 stretch=selfconsistent K1=-433600 K2=-10975000";

// The plugin's force is the physics core's, stretch included (one source of truth).
TEST(FpamActuator, ForceIsThePhysicsCoresAtTheTendonLength) {
  std::string error;
  const auto actuator = create(kTorqueRig, &error);
  ASSERT_TRUE(actuator) << error;
  const auto muscle = physics::paper::torque_measurement_flexor(physics::StretchMode::kSelfConsistent);
  for (double angle : {-1.0, -0.3, 0.0, 0.4, 0.8}) {
    for (double kpa : {0.0, 34.0, 50.0, 137.0}) {
      const auto state = physics::muscle_state(muscle, angle, kpa * 1e3);
      EXPECT_NEAR(actuator->Force(state.path_length, kpa), state.force, 1e-9) << angle << " " << kpa;
    }
  }
}

// routing=planar: the muscle's torque about its own joint is the paper's 2D torque model's (Eqns. tau1, tau2 with
// the mounts' stretch, physics::muscle_state), straight and wrapping, and its path's length rate is -moment arm x
// the joint's rate (virtual work).
TEST(FpamActuator, PlanarTorqueIsThePhysicsCoresAtTheJointAngle) {
  const auto muscle = physics::paper::torque_measurement_flexor(physics::StretchMode::kSelfConsistent);
  FpamConfig config{.law = muscle};
  config.planar = FpamConfig::PlanarPath{muscle.placement, muscle.wrist_radius, muscle.wrap_surface};
  std::string error;
  const auto actuator = create(config.ToText(), &error);
  ASSERT_TRUE(actuator) << error;
  ASSERT_TRUE(actuator->planar());
  int wrapped = 0;
  for (double angle : {-1.0, -0.3, 0.0, 0.4, 0.8}) {
    for (double kpa : {0.0, 34.0, 50.0, 137.0}) {
      const auto state = physics::muscle_state(muscle, angle, kpa * 1e3);
      EXPECT_NEAR(actuator->Torque(angle, kpa), state.torque, 1e-12) << angle << " " << kpa;
      wrapped += state.regime == physics::Regime::kWrapping;
    }
    EXPECT_NEAR(actuator->PathVelocity(angle, 0.7), -physics::muscle_state(muscle, angle, 0.0).moment_arm * 0.7, 1e-15);
  }
  EXPECT_GT(wrapped, 0);
  EXPECT_EQ(actuator->Torque(std::nan(""), 50.0), 0.0);
  const auto spatial = create(kTorqueRig, &error);
  ASSERT_TRUE(spatial) << error;
  EXPECT_FALSE(spatial->planar());
  EXPECT_EQ(spatial->Torque(0.2, 50.0), 0.0);  // a tendon's plugin has no path of its own
}

TEST(FpamActuator, RegulatorIsFirstOrderTowardsTheClampedCommand) {
  std::string error;
  const auto actuator = create("softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 time_constant=0.05", &error);
  ASSERT_TRUE(actuator) << error;
  EXPECT_DOUBLE_EQ(actuator->PressureRate(100.0, 20.0), 80.0 / 0.05);
  EXPECT_DOUBLE_EQ(actuator->PressureRate(500.0, 0.0), 137.0 / 0.05);
  EXPECT_DOUBLE_EQ(actuator->PressureRate(-50.0, 10.0), -10.0 / 0.05);
  EXPECT_EQ(actuator->PressureRate(std::nan(""), 10.0), 0.0);
  EXPECT_EQ(actuator->Force(std::nan(""), 100.0), 0.0);
  EXPECT_EQ(actuator->Force(0.25, std::nan("")), 0.0);
}

// A regulator that vents more slowly than it fills (sim::Regulator): the venting time constant only while the pressure
// falls; without one, the same first order both ways.
TEST(FpamActuator, RegulatorVentsWithItsOwnTimeConstant) {
  std::string error;
  const auto actuator =
      create("softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 time_constant=0.05 vent_time_constant=0.2", &error);
  ASSERT_TRUE(actuator) << error;
  EXPECT_DOUBLE_EQ(actuator->PressureRate(100.0, 20.0), 80.0 / 0.05);
  EXPECT_DOUBLE_EQ(actuator->PressureRate(20.0, 100.0), -80.0 / 0.2);
  EXPECT_EQ(actuator->PressureRate(50.0, 50.0), 0.0);
  const auto config = PluginConfig::Parse(actuator->config().ToText(), &error);
  ASSERT_TRUE(config) << error;
  const auto again = FpamActuator::Create(*config, "flexor", &error);
  ASSERT_TRUE(again) << error;
  EXPECT_DOUBLE_EQ(again->PressureRate(20.0, 100.0), -80.0 / 0.2);
  const auto symmetric = create("softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 time_constant=0.05", &error);
  ASSERT_TRUE(symmetric) << error;
  EXPECT_DOUBLE_EQ(symmetric->PressureRate(20.0, 100.0), -80.0 / 0.05);
  EXPECT_EQ(symmetric->config().ToText().find("vent_time_constant"), std::string::npos);
}

// A second-order regulator (physics/pressure_regulator.h): the rates carry MuJoCo's explicit 1 ms step to the
// physics core's exact state, towards the command clamped to [0, max].
TEST(FpamActuator, SecondOrderRatesStepToThePhysicsCoresState) {
  std::string error;
  const auto actuator =
      create("softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 time_constant=0.05 second_order_time=0.04", &error);
  ASSERT_TRUE(actuator) << error;
  const physics::RegulatorResponse response{.time_constant = 0.05, .second_order_time = 0.04};
  for (const auto& [command, pressure, rate] :
       {std::tuple{100.0, 20.0, 0.0}, {500.0, 50.0, 300.0}, {0.0, 90.0, -40.0}}) {
    const auto rates = actuator->SecondOrderStep(command, pressure, rate, 1e-3);
    const auto exact = physics::regulator_step(response, {pressure, rate}, std::clamp(command, 0.0, 137.0), 1e-3);
    EXPECT_NEAR(pressure + 1e-3 * rates.pressure, exact.pressure, 1e-9) << command;
    EXPECT_NEAR(rate + 1e-3 * rates.pressure_rate, exact.rate, 1e-9) << command;
  }
  const auto stalled = actuator->SecondOrderStep(std::nan(""), 20.0, 0.0, 1e-3);
  EXPECT_EQ(stalled.pressure, 0.0);
  EXPECT_EQ(stalled.pressure_rate, 0.0);
  EXPECT_NE(actuator->config().ToText().find(" second_order_time=0.04"), std::string::npos);
}

// A malformed configuration fails at load with a message naming the actuator and the attribute.
TEST(FpamActuator, MalformedConfigurationsNameActuatorAndAttribute) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"softwrist.fpam r0=0.0123 eps_max=0.28", "attribute 'rest_length': missing"},
      {"softwrist.fpam rest_length=-0.3 r0=0.0123 eps_max=0.28", "attribute 'rest_length': must be > 0"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=1.5", "max_contraction"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123", "attribute 'eps_max': missing"},
      {"softwrist.fpam rest_length=0.3", "give either r0 and eps_max"},
      {"softwrist.fpam rest_length=abc r0=0.0123 eps_max=0.28", "attribute 'rest_length'"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 stretch=sometimes", "attribute 'stretch'"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 stretch=oneshot K2=5", "attribute 'K1'"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 colour=red", "attribute 'colour': unknown"},
      {"softwrist.fpam rest_length=0.3 table_pressure_kpa=0,34 table_r0=0.01 table_eps_max=0.2,0.3", "differ"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 time_constant=0", "attribute 'time_constant'"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 vent_time_constant=-1", "'vent_time_constant'"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 vent_time_constant=500", "'vent_time_constant'"},
      {"softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 second_order_time=-0.1", "'second_order_time'"},
      {"other.plugin rest_length=0.3", "is not softwrist.fpam"},
  };
  for (const auto& [text, expected] : cases) {
    std::string error;
    EXPECT_FALSE(create(text, &error)) << text;
    EXPECT_NE(error.find(expected), std::string::npos) << text << " -> " << error;
    EXPECT_NE(error.find("actuator 'flexor'"), std::string::npos) << error;
  }
  std::string error;
  EXPECT_FALSE(PluginConfig::Parse("softwrist.fpam rest_length", &error));
  EXPECT_FALSE(PluginConfig::Parse("softwrist.fpam a=1 a=2", &error));
  EXPECT_FALSE(PluginConfig::Parse("", &error));
}

}  // namespace
}  // namespace softwrist::plugin
