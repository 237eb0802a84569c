#include "fpam_config.h"

#include <gtest/gtest.h>

#include "physics/paper_parameters.h"

namespace softwrist::plugin {
namespace {

std::optional<FpamConfig> read(const std::string& text, std::string* error) {
  const auto config = PluginConfig::Parse(text, error);
  if (!config) return std::nullopt;
  return FpamConfig::FromConfig(*config, "flexor", error);
}

void expect_same(const FpamConfig& a, const FpamConfig& b) {
  ASSERT_EQ(a.law.fpam.rows().size(), b.law.fpam.rows().size());
  for (std::size_t i = 0; i < a.law.fpam.rows().size(); ++i) {
    EXPECT_DOUBLE_EQ(a.law.fpam.rows()[i].pressure, b.law.fpam.rows()[i].pressure);
    EXPECT_DOUBLE_EQ(a.law.fpam.rows()[i].radius, b.law.fpam.rows()[i].radius);
    EXPECT_DOUBLE_EQ(a.law.fpam.rows()[i].max_contraction, b.law.fpam.rows()[i].max_contraction);
  }
  EXPECT_DOUBLE_EQ(a.law.fpam.fabric().elastic_modulus, b.law.fpam.fabric().elastic_modulus);
  EXPECT_DOUBLE_EQ(a.law.fpam.fabric().thickness, b.law.fpam.fabric().thickness);
  EXPECT_DOUBLE_EQ(a.law.fpam.fabric().elastic_onset_contraction, b.law.fpam.fabric().elastic_onset_contraction);
  EXPECT_DOUBLE_EQ(a.law.fpam.fabric().elastic_curvature, b.law.fpam.fabric().elastic_curvature);
  EXPECT_DOUBLE_EQ(a.law.rest_length, b.law.rest_length);
  EXPECT_EQ(a.law.stretch_mode, b.law.stretch_mode);
  if (a.law.stretch_mode != physics::StretchMode::kNone) {
    EXPECT_DOUBLE_EQ(a.law.mount_stiffness.forearm, b.law.mount_stiffness.forearm);
    EXPECT_DOUBLE_EQ(a.law.mount_stiffness.hand, b.law.mount_stiffness.hand);
    EXPECT_DOUBLE_EQ(a.law.mount_stiffness.exponent, b.law.mount_stiffness.exponent);
    EXPECT_DOUBLE_EQ(a.law.mount_stiffness.preload, b.law.mount_stiffness.preload);
    EXPECT_DOUBLE_EQ(a.law.mount_stiffness.shaped_share, b.law.mount_stiffness.shaped_share);
  }
  EXPECT_DOUBLE_EQ(a.max_pressure_kpa, b.max_pressure_kpa);
  EXPECT_DOUBLE_EQ(a.regulator.time_constant, b.regulator.time_constant);
  EXPECT_DOUBLE_EQ(a.regulator.vent_time_constant, b.regulator.vent_time_constant);
  EXPECT_DOUBLE_EQ(a.regulator.second_order_time, b.regulator.second_order_time);
  EXPECT_DOUBLE_EQ(a.hysteresis.fraction, b.hysteresis.fraction);
  EXPECT_DOUBLE_EQ(a.hysteresis.transition_length, b.hysteresis.transition_length);
  EXPECT_DOUBLE_EQ(a.hysteresis.friction_force, b.hysteresis.friction_force);
  EXPECT_DOUBLE_EQ(a.hysteresis.pressure_friction, b.hysteresis.pressure_friction);
  ASSERT_EQ(a.planar.has_value(), b.planar.has_value());
  if (a.planar) {
    EXPECT_DOUBLE_EQ(a.planar->placement.d1, b.planar->placement.d1);
    EXPECT_DOUBLE_EQ(a.planar->placement.w1, b.planar->placement.w1);
    EXPECT_DOUBLE_EQ(a.planar->placement.d2, b.planar->placement.d2);
    EXPECT_DOUBLE_EQ(a.planar->placement.w2, b.planar->placement.w2);
    EXPECT_DOUBLE_EQ(a.planar->wrist_radius, b.planar->wrist_radius);
    EXPECT_DOUBLE_EQ(a.planar->surface.x, b.planar->surface.x);
    EXPECT_DOUBLE_EQ(a.planar->surface.y, b.planar->surface.y);
    EXPECT_DOUBLE_EQ(a.planar->surface.aspect, b.planar->surface.aspect);
  }
}

// What the model builder writes reads back to the same configuration, for the paper's per-pressure fPAM with
// stretching mounts (Table tensile_testing_parameters, Table torque_measurement_parameters) and for a constant one.
TEST(FpamConfig, WrittenTextReadsBackToItself) {
  const auto rig = physics::paper::torque_measurement_flexor(physics::StretchMode::kSelfConsistent);
  const FpamConfig table{.law = rig, .max_pressure_kpa = 120.0, .regulator = {.time_constant = 0.07}};
  const FpamConfig second_order{.law = rig, .regulator = {.time_constant = 0.07, .second_order_time = 0.03}};
  const FpamConfig constant{.law = {.fpam = physics::paper::design_fpam(), .rest_length = 0.29}};
  const FpamConfig hysteretic{.law = rig, .hysteresis = {.fraction = 0.12, .transition_length = 0.003}};
  const FpamConfig frictional{
      .law = rig, .hysteresis = {.friction_force = 1.2, .pressure_friction = 0.07, .transition_length = 0.004}};
  const FpamConfig curved{.law = {.fpam = physics::FpamParameters::Constant(0.0123, 0.28, {.elastic_curvature = 15.0}),
                                  .rest_length = 0.29}};
  FpamConfig banded{.law = rig};  // mounts whose take-up is not quadratic (physics/mount_stretch.h)
  banded.law.mount_stiffness.exponent = 1.25;
  banded.law.mount_stiffness.preload = 6.5;
  FpamConfig strapped = banded;  // a band in series with mounts of the paper's law
  strapped.law.mount_stiffness.shaped_share = 0.35;
  FpamConfig planar{.law = rig};
  planar.planar = FpamConfig::PlanarPath{rig.placement, rig.wrist_radius, rig.wrap_surface};
  FpamConfig planar_ellipse = planar;
  planar_ellipse.planar->surface = {.x = 0.004, .y = -0.002, .aspect = 1.4};
  for (const FpamConfig& written :
       {table, second_order, constant, hysteretic, frictional, curved, banded, strapped, planar, planar_ellipse}) {
    std::string error;
    const auto back = read(written.ToText(), &error);
    ASSERT_TRUE(back) << written.ToText() << ": " << error;
    expect_same(written, *back);
    EXPECT_EQ(back->ToText(), written.ToText());
  }
}

TEST(FpamConfig, TextNamesEveryAttributeThatApplies) {
  const FpamConfig constant{.law = {.fpam = physics::paper::design_fpam(), .rest_length = 0.29}};
  const std::string text = constant.ToText();
  EXPECT_EQ(text.rfind("softwrist.fpam rest_length=0.29 r0=0.0123 eps_max=0.28 ", 0), 0u) << text;
  EXPECT_EQ(text.find("K1="), std::string::npos) << "no stiffness without stretching: " << text;
  EXPECT_NE(text.find(" stretch=none "), std::string::npos) << text;
  EXPECT_NE(text.find(" max_pressure_kpa=137 time_constant=0.1"), std::string::npos) << text;
  EXPECT_EQ(text.find("hysteresis"), std::string::npos) << "none unless the fabric has it: " << text;
  EXPECT_EQ(text.find("second_order_time"), std::string::npos) << "a first-order regulator: " << text;
}

// The fabric's hysteresis (physics/fpam_hysteresis.h): h within [0, 0.5), a positive transition length, a dry
// friction that is not negative and a pressure friction below 1.
TEST(FpamConfig, HysteresisOutsideItsRangeNamesTheAttribute) {
  std::string error;
  const std::string base = "softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 ";
  EXPECT_TRUE(read(base + "hysteresis=0.2 hysteresis_length=0.004", &error)) << error;
  EXPECT_FALSE(read(base + "hysteresis=0.5", &error));
  EXPECT_NE(error.find("actuator 'flexor': attribute 'hysteresis': must be >= 0 and < 0.5"), std::string::npos)
      << error;
  EXPECT_FALSE(read(base + "hysteresis=0.1 hysteresis_length=0", &error));
  EXPECT_NE(error.find("attribute 'hysteresis_length': must be > 0"), std::string::npos) << error;
  EXPECT_FALSE(read(base + "hysteresis_friction=-2", &error));
  EXPECT_NE(error.find("attribute 'hysteresis_friction': must be >= 0 (N)"), std::string::npos) << error;
  EXPECT_FALSE(read(base + "hysteresis_pressure_friction=1.5", &error));
  EXPECT_NE(error.find("attribute 'hysteresis_pressure_friction': must be >= 0 and < 1"), std::string::npos) << error;
}

// The physics core's rules for the law (L0 at most 10 m, a non-zero stiffness) reach the user named by actuator.
TEST(FpamConfig, ThePhysicsCoresRulesNameTheActuator) {
  std::string error;
  EXPECT_FALSE(read("softwrist.fpam rest_length=12 r0=0.0123 eps_max=0.28", &error));
  EXPECT_NE(error.find("actuator 'flexor': rest_length L0 [m] = 12: must be at most 10"), std::string::npos) << error;
  EXPECT_FALSE(read("softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 stretch=oneshot K1=0 K2=5", &error));
  EXPECT_NE(error.find("actuator 'flexor': mount stiffness K1"), std::string::npos) << error;
  EXPECT_FALSE(
      read("softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 stretch=oneshot K1=3 K2=5 "
           "mount_exponent=12",
           &error));
  EXPECT_NE(error.find("actuator 'flexor': mount law exponent n = 12: must lie in [1, 5]"), std::string::npos) << error;
  EXPECT_FALSE(read("softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 stretch=oneshot K1=3", &error));
  EXPECT_NE(error.find("actuator 'flexor': attribute 'K2': must be given when the mounts stretch"), std::string::npos)
      << error;
}

// routing=planar needs the muscle's 2D path (FpamConfig::PlanarPath), which the physics core validates; the path's
// attributes without it, an unknown routing or a malformed list name the attribute.
TEST(FpamConfig, PlanarRoutingNeedsAValidPath) {
  std::string error;
  const std::string base = "softwrist.fpam rest_length=0.3 r0=0.0123 eps_max=0.28 ";
  const std::string path = "placement=0.1947,0.0493,0.083,0.0338 wrist_radius=0.0399";
  EXPECT_TRUE(read(base + "routing=planar " + path, &error)) << error;
  EXPECT_TRUE(read(base + "routing=planar " + path + " wrap_surface=0.003,0,1.3", &error)) << error;
  EXPECT_TRUE(read(base + "routing=spatial", &error)) << error;
  EXPECT_FALSE(read(base + "routing=diagonal " + path, &error));
  EXPECT_NE(error.find("actuator 'flexor': attribute 'routing': 'diagonal' is not spatial or planar"),
            std::string::npos)
      << error;
  EXPECT_FALSE(read(base + path, &error));
  EXPECT_NE(error.find("attribute 'routing': placement, wrist_radius and wrap_surface need routing=planar"),
            std::string::npos)
      << error;
  EXPECT_FALSE(read(base + "routing=planar wrist_radius=0.0399", &error));
  EXPECT_NE(error.find("attribute 'placement': missing"), std::string::npos) << error;
  EXPECT_FALSE(read(base + "routing=planar placement=0.19,0.05,0.08 wrist_radius=0.0399", &error));
  EXPECT_NE(error.find("attribute 'placement': expected d1,w1,d2,w2"), std::string::npos) << error;
  EXPECT_FALSE(read(base + "routing=planar " + path + " wrap_surface=0,0", &error));
  EXPECT_NE(error.find("attribute 'wrap_surface': expected x,y,aspect"), std::string::npos) << error;
  // The hand mount 1 cm from the joint, inside a 4 cm wrist.
  EXPECT_FALSE(read(base + "routing=planar placement=0.19,0.05,0.01,0.0 wrist_radius=0.04", &error));
  EXPECT_NE(error.find("actuator 'flexor': attribute 'placement': "), std::string::npos) << error;
}

}  // namespace
}  // namespace softwrist::plugin
