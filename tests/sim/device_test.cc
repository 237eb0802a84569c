#include "sim/device.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/text_file.h"
#include "physics/errors.h"
#include "physics/units.h"
#include "sim/model_builder.h"

namespace softwrist::sim {
namespace {

const std::filesystem::path kModels = std::filesystem::path(SOFTWRIST_SOURCE_DIR) / "models";

// The shipped default device is exactly what the code generates, so neither can rot.
TEST(PaperDevice, ShippedPlacementFileAndModelMatchTheGenerator) {
  EXPECT_EQ(io::read_text_file(kModels / "paper_device.json"), device_to_json(paper_device()));
  EXPECT_EQ(io::read_text_file(kModels / "paper_device.xml"),
            build_model_xml(load_device(kModels / "paper_device.json")));
  EXPECT_EQ(io::read_text_file(kModels / "rom_device.json"), device_to_json(rom_device()));
  // The torque rig (Table torque_measurement_parameters) is the paper's device: its flexor is the rig's.
  EXPECT_EQ(io::read_text_file(kModels / "torque_rig.json"), device_to_json(paper_device()));
}

// Table torque_measurement_parameters for the flexor, Table RoM for the other three.
TEST(PaperDevice, UsesThePapersTables) {
  const DeviceDescription d = paper_device();
  EXPECT_DOUBLE_EQ(d.muscles[kFlexor].placement.d1, 0.1947);
  EXPECT_DOUBLE_EQ(d.muscles[kFlexor].rest_length, 0.32);
  EXPECT_DOUBLE_EQ(d.muscles[kFlexor].wrist_radius, 0.0399);
  EXPECT_DOUBLE_EQ(d.muscles[kExtensor].placement.d1, 0.245);
  EXPECT_DOUBLE_EQ(d.muscles[kUlnar].placement.d2, 0.010);
  EXPECT_DOUBLE_EQ(d.muscles[kRadial].rest_length, 0.27);
  EXPECT_EQ(d.fpam.rows().size(), 5u);
}

TEST(PlacementFile, RoundTrips) {
  DeviceDescription d = paper_device();
  d.fpam = physics::FpamParameters::Constant(0.0123, 0.28);
  d.stretch_mode = physics::StretchMode::kNone;
  d.regulator.time_constant = 0.05;
  d.regulator.vent_time_constant = 0.15;
  d.regulator.second_order_time = 0.03;
  d.wrist.limit_stiffening = {.torque = 1.5, .angle_scale = units::deg_to_rad(10.0)};
  d.wrist.stiffness_asymmetry_fe = -0.3;
  const std::string text = device_to_json(d);
  EXPECT_EQ(device_to_json(parse_device(text, "x.json")), text);
  EXPECT_DOUBLE_EQ(parse_device(text, "x.json").wrist.limit_stiffening.torque, 1.5);
  EXPECT_DOUBLE_EQ(parse_device(text, "x.json").wrist.stiffness_asymmetry_fe, -0.3);
  EXPECT_EQ(device_to_json(paper_device()).find("stiffness_asymmetry"), std::string::npos);
  EXPECT_DOUBLE_EQ(parse_device(text, "x.json").regulator.vent_time_constant, 0.15);
  EXPECT_DOUBLE_EQ(parse_device(text, "x.json").regulator.second_order_time, 0.03);
  // A fabric other than the paper's (a J-shaped one) is written, read back, and changes the text the replays' caches
  // key on; the paper's is not written.
  DeviceDescription curved = d;
  curved.fpam = d.fpam.with_fabric({.elastic_modulus = 12e6, .elastic_curvature = 18.0});
  const std::string curved_text = device_to_json(curved);
  EXPECT_NE(curved_text, text);
  EXPECT_EQ(parse_device(curved_text, "x.json").fpam.fabric(), curved.fpam.fabric());
  EXPECT_EQ(device_to_json(parse_device(curved_text, "x.json")), curved_text);
  EXPECT_EQ(text.find("\"fabric\""), std::string::npos);
  // A wrist circle off the joint (physics::WrapSurface) likewise; at the joint, nothing is written.
  DeviceDescription moved = d;
  moved.muscles[kUlnar].wrap_surface = {.x = 0.004, .y = -0.003};
  const std::string moved_text = device_to_json(moved);
  EXPECT_NE(moved_text.find("wrap_centre_x_cm"), std::string::npos);
  EXPECT_NEAR(parse_device(moved_text, "x.json").muscles[kUlnar].wrap_surface.y, -0.003, 1e-15);
  EXPECT_TRUE(parse_device(moved_text, "x.json").muscles[kFlexor].wrap_surface.at_joint());
  EXPECT_EQ(device_to_json(parse_device(moved_text, "x.json")), moved_text);
  EXPECT_EQ(text.find("wrap_centre"), std::string::npos);
  // A wrist surface that is not a circle likewise (wrap_aspect, written only when not 1).
  DeviceDescription elliptic = d;
  elliptic.muscles[kExtensor].wrap_surface.aspect = 1.3;
  const std::string elliptic_text = device_to_json(elliptic);
  EXPECT_DOUBLE_EQ(parse_device(elliptic_text, "x.json").muscles[kExtensor].wrap_surface.aspect, 1.3);
  EXPECT_TRUE(parse_device(elliptic_text, "x.json").muscles[kFlexor].wrap_surface.circular());
  EXPECT_EQ(device_to_json(parse_device(elliptic_text, "x.json")), elliptic_text);
  EXPECT_EQ(text.find("wrap_aspect"), std::string::npos);
  // A muscle's own fPAM against the table (r0_scale, eps_max_shift; written only when not the table's), which the
  // muscle's law (what its plugin holds) and its analytic torque use.
  DeviceDescription own_fpam = d;
  own_fpam.muscles[kRadial].fpam_radius_scale = 1.02;
  own_fpam.muscles[kRadial].fpam_max_contraction_shift = -0.004;
  const std::string own_text = device_to_json(own_fpam);
  const DeviceDescription own_read = parse_device(own_text, "x.json");
  EXPECT_DOUBLE_EQ(own_read.muscles[kRadial].fpam_radius_scale, 1.02);
  EXPECT_DOUBLE_EQ(own_read.muscles[kRadial].fpam_max_contraction_shift, -0.004);
  EXPECT_EQ(device_to_json(own_read), own_text);
  EXPECT_EQ(text.find("r0_scale"), std::string::npos);
  EXPECT_EQ(text.find("eps_max_shift"), std::string::npos);
  EXPECT_DOUBLE_EQ(own_read.muscle(kRadial).fpam.at_pressure(0.0).radius, 1.02 * d.fpam.at_pressure(0.0).radius);
  EXPECT_DOUBLE_EQ(own_read.muscle(kRadial).fpam.at_pressure(0.0).max_contraction,
                   d.fpam.at_pressure(0.0).max_contraction - 0.004);
  EXPECT_DOUBLE_EQ(own_read.muscle(kUlnar).fpam.at_pressure(0.0).radius, d.fpam.at_pressure(0.0).radius);
  // An ellipse whose semi-axis along the forearm (3.7 cm) is longer than the ulnar hand mount's distance from O (3.54
  // cm, Table RoM) loads: the mount would meet it at 62.5 deg of radial deviation, beyond the deviation's reach (54.1
  // deg, muscle_reach); with the deviation's limits at 60 deg (reach 75 deg), it is refused.
  DeviceDescription long_wrist = d;
  long_wrist.muscles[kUlnar].wrap_surface.aspect = 0.037 / long_wrist.muscles[kUlnar].wrist_radius;
  EXPECT_NO_THROW(parse_device(device_to_json(long_wrist), "x.json"));
  long_wrist.wrist.radial_limit = long_wrist.wrist.ulnar_limit = units::deg_to_rad(60.0);
  EXPECT_THROW(check_hand_mount_clearance(long_wrist), physics::InvalidParameter);
  // Mounts whose take-up is not quadratic (physics/mount_stretch.h) likewise; the paper's law writes neither.
  DeviceDescription banded = paper_device();
  banded.mount_stiffness.exponent = 1.0;
  banded.mount_stiffness.preload = 8.0;
  const std::string banded_text = device_to_json(banded);
  EXPECT_DOUBLE_EQ(parse_device(banded_text, "x.json").mount_stiffness.exponent, 1.0);
  EXPECT_DOUBLE_EQ(parse_device(banded_text, "x.json").mount_stiffness.preload, 8.0);
  EXPECT_EQ(device_to_json(parse_device(banded_text, "x.json")), banded_text);
  EXPECT_EQ(banded_text.find("shaped_share"), std::string::npos) << "the shaped law alone, the default";
  banded.mount_stiffness.shaped_share = 0.4;  // a band in series with mounts of the paper's law
  const std::string strapped_text = device_to_json(banded);
  EXPECT_DOUBLE_EQ(parse_device(strapped_text, "x.json").mount_stiffness.shaped_share, 0.4);
  EXPECT_EQ(device_to_json(parse_device(strapped_text, "x.json")), strapped_text);
  EXPECT_EQ(device_to_json(paper_device()).find("preload_n"), std::string::npos);
  // A file without a venting time constant keeps none, and is written without one.
  const std::string symmetric = device_to_json(paper_device());
  EXPECT_EQ(symmetric.find("vent_time_constant_s"), std::string::npos);
  EXPECT_EQ(symmetric.find("second_order_time_s"), std::string::npos) << "a first-order regulator";
  EXPECT_EQ(parse_device(symmetric, "x.json").regulator.vent_time_constant, 0.0);
  nlohmann::json zero = nlohmann::json::parse(symmetric);
  zero["regulator"]["vent_time_constant_s"] = 0;  // stated as "the same as time_constant_s"
  EXPECT_EQ(parse_device(zero.dump(), "x.json").regulator.vent_time_constant, 0.0);
}

// A malformed placement file is rejected with the file, the field and the problem.
TEST(PlacementFile, MalformedFilesNameTheFieldAndProblem) {
  const auto base = nlohmann::json::parse(device_to_json(paper_device()));
  auto with = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = base;
    edit(j);
    return j.dump();
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{", "user.json: not valid JSON"},
      {"[1,2]", "user.json: (top level): must be a JSON object"},
      {with([](auto& j) { j["muscles"].erase("ulnar"); }), "user.json: muscles.ulnar: missing"},
      {with([](auto& j) { j["muscles"]["flexor"].erase("L0_cm"); }), "muscles.flexor.L0_cm: missing"},
      {with([](auto& j) { j["muscles"]["flexor"]["d1_cm"] = "far"; }), "muscles.flexor.d1_cm: must be a number"},
      {with([](auto& j) { j["muscles"]["flexor"]["L0_cm"] = -3; }), "muscles.flexor: rest_length"},
      {with([](auto& j) { j["muscles"]["ulnar"]["rw_cm"] = 4; }), "muscles.ulnar: hand mount distance R2"},
      {with([](auto& j) { j["muscles"]["flexor"]["wrap_centre_x_cm"] = 8; }),
       "muscles.flexor: hand mount distance |P2 - C| / r_w"},
      // Outside the circle at zero, inside it at -22 deg, within the flexion's reach (sim::muscle_reach).
      {with([](auto& j) { j["muscles"]["flexor"]["wrap_centre_x_cm"] = 5; }),
       "muscles: flexor: the hand mount comes inside the wrist surface within +-95.9 deg"},
      {with([](auto& j) { j["muscles"]["flexor"]["wrap_aspect"] = 9; }), "muscles.flexor: wrap surface aspect"},
      {with([](auto& j) { j["muscles"]["radial"]["r0_scale"] = -1; }), "muscles.radial.r0_scale: must be > 0"},
      {with([](auto& j) { j["muscles"]["radial"]["eps_max_shift"] = 0.3; }),
       "muscles.radial: max_contraction eps_max = 0.4"},
      {with([](auto& j) { j["muscles"]["flexor"]["d1"] = 3; }), "muscles.flexor.d1: unknown field"},
      {with([](auto& j) { j["fpam"]["table"][4]["eps_max"] = 0.9; }), "fpam.table: max_contraction"},
      {with([](auto& j) { j["fpam"]["table"][1].erase("r0_cm"); }), "fpam.table[1].r0_cm: missing"},
      {with([](auto& j) { j["fpam"]["fabric"]["elastic_curvature"] = -2; }), "fpam.fabric: elastic_curvature"},
      {with([](auto& j) { j["fpam"]["fabric"]["modulus"] = 2; }), "fpam.fabric.modulus: unknown field"},
      // The hysteresis's ranges are the physics core's (physics::hysteresis_problem), named by the file's fields.
      {with([](auto& j) { j["fpam"]["hysteresis"] = 0.5; }), "fpam.hysteresis: must be >= 0 and < 0.5, got 0.5"},
      {with([](auto& j) { j["fpam"]["hysteresis_friction_n"] = -2; }),
       "fpam.hysteresis_friction_n: must be >= 0 (N), got -2"},
      {with([](auto& j) { j["fpam"]["hysteresis_pressure_friction"] = 1.5; }),
       "fpam.hysteresis_pressure_friction: must be >= 0 and < 1, got 1.5"},
      {with([](auto& j) { j["fpam"]["hysteresis_length_mm"] = 0; }), "fpam.hysteresis_length_mm: must be"},
      {with([](auto& j) { j["stretch"]["mode"] = "maybe"; }), "stretch.mode: 'maybe'"},
      {with([](auto& j) { j["stretch"]["K1_n_per_cm2"] = 0; }), "stretch: mount stiffness K1"},
      {with([](auto& j) { j["stretch"]["preload_n"] = -2; }), "stretch: mount preload F_p [N] = -2"},
      {with([](auto& j) {
         j["stretch"]["mode"] = "none";  // not used, but written back as read: checked all the same
         j["stretch"]["exponent"] = 9;
       }),
       "stretch: mount law exponent n = 9: must lie in [1, 5]"},
      {with([](auto& j) { j["regulator"]["max_pressure_kpa"] = -1; }), "regulator.max_pressure_kpa: must be > 0"},
      {with([](auto& j) { j["regulator"]["vent_time_constant_s"] = 1e4; }), "regulator.vent_time_constant_s"},
      {with([](auto& j) { j["regulator"]["vent_time_constant_s"] = -1; }), "regulator.vent_time_constant_s"},
      {with([](auto& j) { j["regulator"]["second_order_time_s"] = -0.01; }), "regulator.second_order_time_s"},
      {with([](auto& j) { j["regulator"]["second_order_time_s"] = 1e3; }), "regulator.second_order_time_s"},
      {with([](auto& j) { j["wrist"]["damping_fe_nms_per_rad"] = -1; }), "wrist.damping_fe_nms_per_rad"},
      {with([](auto& j) { j["wrist"]["limit_stiffening_nm"] = 50; }), "wrist.limit_stiffening_nm: must lie in [0, 20]"},
      {with([](auto& j) { j["wrist"]["limit_stiffening_scale_deg"] = 1; }), "wrist.limit_stiffening_scale_deg"},
      {with([](auto& j) { j["stretch"]["shaped_share"] = 1.5; }), "must lie in [0, 1]"},
      {with([](auto& j) { j["wrist"]["stiffness_asymmetry_ur"] = 1.2; }),
       "wrist.stiffness_asymmetry_ur: must lie in [-0.9, 0.9]"},
      {with([](auto& j) { j["format"] = "other/2"; }), "format: 'other/2'"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_device(text, "user.json");
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(load_device("/nonexistent/user.json"), std::runtime_error);
}

}  // namespace
}  // namespace softwrist::sim
