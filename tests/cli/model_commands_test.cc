#include "cli/model_commands.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "cli/run_cli_for_test.h"
#include "physics/paper_parameters.h"
#include "physics/units.h"

namespace softwrist::cli {
namespace {

using nlohmann::json;

TEST(ModelTorque, DefaultsToTheTorqueRigFlexorAndMatchesThePhysicsCore) {
  const auto r = run({"model", "torque", "--pressure-kpa", "103", "--stretch", "selfconsistent", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = json::parse(r.out);
  ASSERT_EQ(j["angles_deg"].size(), 8u);
  const auto flexor = physics::paper::torque_measurement_flexor(physics::StretchMode::kSelfConsistent);
  for (std::size_t i = 0; i < 8; ++i) {
    const double angle = j["angles_deg"][i];
    const auto state = physics::muscle_state(flexor, units::deg_to_rad(angle), 103e3);
    EXPECT_DOUBLE_EQ(j["torque_nm"][i].get<double>(), state.torque);
    EXPECT_EQ(j["regime"][i], physics::to_string(state.regime));
  }
}

// The design-optimization curve from the command line, as the issue states it.
TEST(ModelTorque, DesignCurveStopsWrappingNearMinusOneDegree) {
  const auto r = run({"model", "torque", "--pressure-kpa", "137", "--angles", "-2:0:0.1", "--placement", "22,3.5,9,1.5",
                      "--L0-from-angle", "-65.4", "--rw", "2", "--r0", "1.23", "--eps-max", "0.28", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = json::parse(r.out);
  EXPECT_EQ(j["regime"].front(), "wrapping");
  EXPECT_EQ(j["regime"].back(), "straight");
}

TEST(ModelRom, PrintsFourLimitsBesideThePapers) {
  const auto r = run({"model", "rom", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = json::parse(r.out);
  for (const char* key : {"flexion_deg", "extension_deg", "ulnar_deg", "radial_deg"}) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_GT(j[key].get<double>(), 0.0);
    EXPECT_LT(j[key].get<double>(), 90.0);
  }
  EXPECT_NEAR(j["paper_modeled_deg"]["flexion_deg"].get<double>(), 49.8, 1e-9);
  // The reported eps_max_matching_paper is the one that moves our limit onto the paper's modeled limit.
  const double eps = j["eps_max_matching_paper"]["flexion"];
  const auto m = json::parse(run({"model", "rom", "--json", "--r0", "1.26", "--eps-max", std::to_string(eps)}).out);
  EXPECT_NEAR(m["flexion_deg"].get<double>(), 49.8, 1e-3);
  // An override changes only its own muscle.
  const auto o = json::parse(run({"model", "rom", "--json", "--flexion", "22,3.5,9,1.5,33.35"}).out);
  EXPECT_NE(o["flexion_deg"], j["flexion_deg"]);
  EXPECT_EQ(o["radial_deg"], j["radial_deg"]);
}

TEST(ModelTables, WritesTheMainJobsFiles) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("softwrist_model_tables_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const auto r = run({"model", "tables", "--out", dir.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Range of motion"), std::string::npos);
  for (const char* name : {"model_tables.md", "torque.json", "rom.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  }
  std::filesystem::remove_all(dir);
}

// `model build` writes a model that loads with the plugin; from a placement file it equals the shipped model.
TEST(ModelBuild, WritesTheModelOfAPlacementFile) {
  const auto out =
      std::filesystem::temp_directory_path() / ("softwrist_model_build_test_" + std::to_string(::getpid()) + ".xml");
  const auto r = run({"model", "build", "--placement", std::string(SOFTWRIST_SOURCE_DIR) + "/models/paper_device.json",
                      "--out", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream built(out), shipped(std::string(SOFTWRIST_SOURCE_DIR) + "/models/paper_device.xml");
  std::stringstream a, b;
  a << built.rdbuf();
  b << shipped.rdbuf();
  EXPECT_EQ(a.str(), b.str());
  std::filesystem::remove(out);
}

// Bad arguments: a clear message naming the problem, a non-zero exit, never a crash.
TEST(ModelCommands, BadArgumentsGiveAClearErrorAndNonZeroExit) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"model", "torque", "--pressure-kpa", "-5"}, "--pressure-kpa"},
      {{"model", "torque", "--pressure-kpa", "500"}, "--pressure-kpa"},
      {{"model", "torque", "--pressure-kpa", "nan"}, "--pressure-kpa"},
      {{"model", "torque", "--pressure-kpa", "abc"}, "--pressure-kpa"},
      {{"model", "torque", "--angles", "10:0:1"}, "--angles"},
      {{"model", "torque", "--placement", "1,2,3"}, "--placement"},
      {{"model", "torque", "--placement", "22,3.5,1,0.5"}, "R2"},
      {{"model", "torque", "--r0", "1.2", "--eps-max", "1.5"}, "max_contraction"},
      {{"model", "torque", "--r0", "1.2"}, "--eps-max"},
      {{"model", "torque", "--L0", "-3"}, "rest_length"},
      {{"model", "torque", "--L0", "30", "--L0-from-angle", "-60"}, "excludes"},
      {{"model", "torque", "--stretch", "sometimes"}, "--stretch"},
      {{"model", "torque", "--stretch", "oneshot", "--K1", "0"}, "K1"},
      {{"model", "torque", "--fpam-table", "other"}, "--fpam-table"},
      {{"model", "rom", "--flexion", "1,2,3"}, "--flexion"},
      {{"model", "rom", "--rw", "4"}, "R2"},
      {{"model", "build", "--placement", "/nonexistent.json", "--out", "/tmp/x.xml"}, "--placement"},
      {{"model", "build"}, "--out"},
      {{"render", "--pressures-kpa", "200,0,0,0", "--out", "/tmp/x.png"}, "--pressures-kpa"},
      {{"render", "--pressures-kpa", "1,2", "--out", "/tmp/x.png"}, "--pressures-kpa"},
      {{"render", "--view", "top", "--out", "/tmp/x.png"}, "--view"},
      {{"render"}, "--out PNG is required (or --run RUN_DIR)"},
      {{"render", "--at", "3", "--out", "/tmp/x.png"}, "--at requires --run"},
      {{"render", "--run", "/tmp", "--fe-deg", "3"}, "--fe-deg excludes --run"},
      {{"render", "--run", "/tmp", "--fps", "10"}, "--fps requires --video"},
      {{"render", "--run", "/nonexistent"}, "--run"},
      {{"bench", "sim", "--steps", "5"}, "--steps"},
      {{"model", "bogus"}, "subcommand"},
      {{"model"}, "subcommand"},
      {{}, "subcommand"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = run(args);
    std::string joined;
    for (const auto& a : args) joined += a + " ";
    EXPECT_NE(r.code, 0) << joined;
    EXPECT_NE(r.err.find(expected), std::string::npos) << joined << "-> " << r.err;
  }
}

TEST(ModelCommands, HelpSucceeds) {
  const auto r = run({"model", "torque", "--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--pressure-kpa"), std::string::npos);
}

}  // namespace
}  // namespace softwrist::cli
