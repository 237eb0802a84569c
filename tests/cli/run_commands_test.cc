// `softwrist run`, `merge`, `personalize`, `bench optimize`, `bench control`, `bench render`, and the bridge's
// `trial`, `emulate` and `bench bridge` argument errors from the command line (the bridge itself runs against the
// emulator in tests/bridge/bridge_emulator_test.cc).

#include "cli/run_commands.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/run_cli_for_test.h"
#include "optimize/design_optimizer.h"
#include "optimize/personalize.h"
#include "sim/device.h"
#include "sim/model.h"
#include "support/scratch_dir_test.h"

namespace softwrist::cli {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
const fs::path kSource = SOFTWRIST_SOURCE_DIR;

using CliRun = softwrist::testing::ScratchDirTest;

TEST_F(CliRun, RunShardsAndMerge) {
  const std::string config = (kSource / "experiments/range_of_motion.json").string();
  for (const char* shard : {"1/2", "2/2"}) {
    const auto r =
        run({"run", config, "--quiet", "--shard", shard, "--out", (dir_ / (std::string("s") + shard[0])).string()});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("softwrist merge"));
  }
  const auto merged = run({"merge", "--out", (dir_ / "all").string(), (dir_ / "s1").string(), (dir_ / "s2").string()});
  ASSERT_EQ(merged.code, 0) << merged.err;
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "all/summary.json"));
  EXPECT_EQ(summary["muscles"].size(), 4u);

  EXPECT_EQ(run({"run", config, "--shard", "3/2"}).code, 2);
  const auto missing = run({"merge", "--out", (dir_ / "x").string(), (dir_ / "s1").string()});
  EXPECT_EQ(missing.code, 1);
  EXPECT_THAT(missing.err, HasSubstr("error: merge: cases missing"));
  std::ofstream(dir_ / "bad.json") << R"({"format": "softwrist.experiment/1", "kind": "range_of_motion"})";
  const auto bad = run({"run", (dir_ / "bad.json").string()});
  EXPECT_EQ(bad.code, 1);
  EXPECT_THAT(bad.err, HasSubstr("bad.json: model: missing"));
}

// The example user with a coarse start grid: the four placements lie within the bounds the arm dimensions give, the
// flexor's equals the design optimization of the same problem, and the written files load.
TEST_F(CliRun, PersonalizeWritesALoadablePlacementAndModel) {
  auto user = nlohmann::json::parse(std::ifstream(kSource / "experiments/example_user.json"));
  for (auto& [muscle, file] : user["references"].items())
    file = (kSource / "experiments" / file.get<std::string>()).string();
  user["start_resolution_cm"] = {{"d1", 5.0}, {"w1", 1.5}, {"d2", 2.5}, {"w2", 1.0}};
  std::ofstream(dir_ / "user.json") << user.dump();
  const auto r = run({"personalize", "--user", (dir_ / "user.json").string(), "--out", (dir_ / "out").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const sim::DeviceDescription device = sim::load_device(dir_ / "out/placement.json");
  const optimize::UserDescription described = optimize::load_user(dir_ / "user.json");
  for (int i = 0; i < 4; ++i) {
    const auto& p = device.muscles[static_cast<std::size_t>(i)].placement;
    const auto& b = described.bounds[static_cast<std::size_t>(i)];
    EXPECT_TRUE(p.d1 >= b.lower.d1 && p.d1 <= b.upper.d1 && p.w1 >= b.lower.w1 && p.w1 <= b.upper.w1 &&
                p.d2 >= b.lower.d2 && p.d2 <= b.upper.d2 && p.w2 >= b.lower.w2 && p.w2 <= b.upper.w2)
        << i;
  }
  optimize::OptimizerOptions options;
  options.start_resolution = described.start_resolution;
  const auto flexor = optimize::optimize_design(optimize::user_design_problem(described, 0), options);
  EXPECT_NEAR(device.muscles[0].placement.d2, flexor.best.placement.d2, 1e-9);
  EXPECT_NEAR(device.muscles[0].placement.d2, 0.09, 1e-4);  // Table optimized_parameters
  EXPECT_NO_THROW(sim::Model::FromFile(dir_ / "out/model.xml", sim::PluginSet::Default()));

  user["wrist"]["range_deg"].erase("radial");
  std::ofstream(dir_ / "user2.json") << user.dump();
  const auto bad = run({"personalize", "--user", (dir_ / "user2.json").string()});
  EXPECT_EQ(bad.code, 1);
  EXPECT_THAT(bad.err, HasSubstr("user2.json: wrist.range_deg.radial: missing"));
}

TEST(CliBench, OptimizeJsonHasTheIssuesKeys) {
  const auto r = run({"bench", "optimize", "--json", "--config",
                      (kSource / "experiments/design_optimization.json").string(), "--exhaustive-resolution-cm", "1"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"wall_s", "evaluations", "placement_cm", "objective", "same_optimum", "global_optimum_wall_s",
                          "objective_evaluations_per_s"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["placement_cm"].size(), 4u);
  EXPECT_TRUE(j["same_optimum"].get<bool>());
}

// The benchmark reports every controller of the config over the whole trajectory (110 s of planar steps), with
// its real-time factor (the figure itself is the benchmark's business, not a test's); a config of another kind is
// refused.
TEST(CliBench, ControlReportsEveryControllerOverTheTrajectory) {
  const auto r =
      run({"bench", "control", "--json", "--config", (kSource / "experiments/planar_tracking.json").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["controllers"].size(), 2u);
  for (const auto& c : j["controllers"]) {
    EXPECT_DOUBLE_EQ(c["simulated_s"].get<double>(), 110.0);
    EXPECT_GT(c["real_time_factor"].get<double>(), 0.0);
  }
  EXPECT_EQ(j["controllers"][0]["controller"], "paper");
}

// The plugin benchmark's baseline replays the plugin's forces through MuJoCo's own actuators: the two runs move bit
// for bit alike, so its ratio is the plugin's cost alone (the ratio itself is the benchmark's business).
TEST(CliBench, SimReplaysThePluginsForcesWithTheSameMotion) {
  const auto r = run({"bench", "sim", "--json", "--steps", "3000", "--rounds", "1"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["same_motion"].get<bool>());
  EXPECT_EQ(j["max_joint_difference_rad"].get<double>(), 0.0);
  EXPECT_GT(j["ratio"].get<double>(), 0.0);
}

// The render benchmark draws real frames at both sizes and reports positive rates and the first frame's cost; a bad
// frame count is a usage error.
TEST(CliBench, RenderReportsFramesPerSecond) {
  const auto r = run({"bench", "render", "--json", "--frames", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["fps_640x480"].get<double>(), 0.0);
  EXPECT_GT(j["fps_320x240"].get<double>(), 0.0);
  EXPECT_GT(j["fps_640x480_viewer_look"].get<double>(), 0.0);
  EXPECT_GT(j["first_frame_s_640x480"].get<double>(), 0.0);
  EXPECT_EQ(run({"bench", "render", "--frames", "0"}).code, 2);
  const auto wrong = run({"bench", "control", "--config", (kSource / "experiments/range_of_motion.json").string()});
  EXPECT_NE(wrong.code, 0);
  EXPECT_THAT(wrong.err, HasSubstr("is not a tracking experiment config"));
}

// Bad arguments to the bridge's commands are named before anything opens or moves.
TEST_F(CliRun, BridgeCommandsNameTheirBadArguments) {
  const std::string config = (kSource / "experiments/planar_rehearsal.json").string();
  const auto no_device = run({"trial", config, "--device", "/nonexistent/ttyACM9", "--out", (dir_ / "t").string()});
  EXPECT_EQ(no_device.code, 1);
  EXPECT_THAT(no_device.err, HasSubstr("/nonexistent/ttyACM9: cannot open"));
  EXPECT_FALSE(fs::exists(dir_ / "t" / "trials.csv"));
  const auto too_high = run({"trial", config, "--device", "/dev/null", "--max-kpa", "500"});
  EXPECT_EQ(too_high.code, 2);
  EXPECT_THAT(too_high.err, HasSubstr("--max-kpa"));
  const auto no_timeout = run({"trial", config, "--device", "/dev/null", "--timeout-ms", "0"});
  EXPECT_EQ(no_timeout.code, 2);
  EXPECT_THAT(no_timeout.err, HasSubstr("--timeout-ms must be 1..1000"));
  const auto not_a_tty = run({"trial", config, "--device", "/dev/null", "--out", (dir_ / "t").string()});
  EXPECT_EQ(not_a_tty.code, 1);
  EXPECT_THAT(not_a_tty.err, HasSubstr("/dev/null: not a serial device"));
  const auto both = run({"trial", config, "--device", "/dev/null", "--emulator", config});
  EXPECT_EQ(both.code, 2);
  EXPECT_THAT(both.err, HasSubstr("excludes"));
  const auto firmware_on_device = run({"trial", config, "--device", "/dev/null", "--firmware", config});
  EXPECT_EQ(firmware_on_device.code, 2);
  EXPECT_THAT(firmware_on_device.err, HasSubstr("excludes"));
  const auto neither = run({"trial", config});
  EXPECT_EQ(neither.code, 2);
  EXPECT_THAT(neither.err, HasSubstr("give one of --device and --emulator"));
  std::ofstream(dir_ / "emulator.json") << R"({"format": "softwrist.emulator/1", "model": "x.json",
      "effects": {"regulator_lag": {"time_constant_s": -0.1}}})";
  const auto bad_emulator = run({"emulate", (dir_ / "emulator.json").string(), "--duration-s", "1"});
  EXPECT_EQ(bad_emulator.code, 1);
  EXPECT_THAT(bad_emulator.err, HasSubstr("effects.regulator_lag.time_constant_s"));
  EXPECT_EQ(run({"bench", "bridge", "--cycles", "3"}).code, 2);
}

}  // namespace
}  // namespace softwrist::cli

namespace softwrist::cli {
namespace {

// The rehearsal of scripts/main.sh: the trial against the emulator on one simulated clock (--emulator). Its log is
// the same whole log on any machine however busy (issue 27), so two runs agree row for row.
TEST_F(CliRun, TrialAgainstTheEmulatorInSimulatedTimeIsRepeatable) {
  const std::string config = (kSource / "experiments/planar_rehearsal.json").string();
  const std::string emulator = (kSource / "experiments/emulator/realistic.json").string();
  std::string logs[2];
  for (int k = 0; k < 2; ++k) {
    const fs::path out = dir_ / ("t" + std::to_string(k));
    const auto r = run({"trial", config, "--emulator", emulator, "--controller", "paper", "--out", out.string()});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("1 of 1 runs on the emulator"));
    std::ifstream in(out / "trials.csv");
    std::stringstream text;
    text << in.rdbuf();
    logs[k] = text.str();
  }
  // 16 s of steps at the 14 ms loop: over a thousand rows, every one of them alike in both runs.
  EXPECT_GT(std::count(logs[0].begin(), logs[0].end(), '\n'), 1000);
  EXPECT_EQ(logs[0], logs[1]);
}

// `softwrist calibrate`: bad arguments are named before anything moves; a fault during the routine ends it vented,
// and the command fails naming the fault and the parts that did not run, after writing what the rest identified
// (the fit itself is tested in tests/calibration/calibration_test.cc).
TEST_F(CliRun, CalibrateNamesBadArgumentsAndAnInterruptedRoutine) {
  const std::string placement = (kSource / "models/rom_device.json").string();
  const std::string emulator = (kSource / "experiments/emulator/realistic.json").string();
  const std::string routine = (kSource / "experiments/calibration_routine.json").string();
  EXPECT_EQ(run({"calibrate", "--emulator", emulator, "--out", (dir_ / "c").string()}).code, 2);  // no --placement
  const auto both = run({"calibrate", "--device", "/dev/null", "--emulator", emulator, "--placement", placement,
                         "--out", (dir_ / "c").string()});
  EXPECT_EQ(both.code, 2);
  const auto not_routine =
      run({"calibrate", "--emulator", emulator, "--placement", placement, "--routine",
           (kSource / "experiments/planar_rehearsal.json").string(), "--out", (dir_ / "c").string()});
  EXPECT_EQ(not_routine.code, 1);
  EXPECT_THAT(not_routine.err, HasSubstr("not a calibration routine"));

  // The IMUs stop answering 14 s in: the flexor's steps ran, the rest did not.
  nlohmann::json faulty = nlohmann::json::parse(std::ifstream(emulator));
  faulty["model"] = placement;
  faulty["faults"] = {{"imu_stale_at_s", 14.0}};
  std::ofstream(dir_ / "faulty.json") << faulty.dump();
  const auto stopped = run({"calibrate", "--emulator", (dir_ / "faulty.json").string(), "--placement", placement,
                            "--routine", routine, "--out", (dir_ / "stopped").string()});
  EXPECT_EQ(stopped.code, 1);
  EXPECT_THAT(stopped.err, HasSubstr("the routine stopped after"));
  EXPECT_THAT(stopped.err, HasSubstr("IMU"));
  EXPECT_THAT(stopped.err, HasSubstr("not run: flexor ramp, extensor steps"));
  const nlohmann::json record = nlohmann::json::parse(std::ifstream(dir_ / "stopped" / "calibration.json"));
  EXPECT_THAT(record["not_identified"].dump(), HasSubstr("\"what\":\"radial ramp\""));
  EXPECT_TRUE(fs::exists(dir_ / "stopped" / "calibrated.json"));

  // 5 s in: too little to fit anything, and no calibrated file.
  faulty["faults"] = {{"imu_stale_at_s", 5.0}};
  std::ofstream(dir_ / "faulty.json") << faulty.dump();
  const auto early = run({"calibrate", "--emulator", (dir_ / "faulty.json").string(), "--placement", placement,
                          "--routine", routine, "--out", (dir_ / "early").string()});
  EXPECT_EQ(early.code, 1);
  EXPECT_THAT(early.err, HasSubstr("nothing was identified"));
  EXPECT_FALSE(fs::exists(dir_ / "early" / "calibrated.json"));
}

}  // namespace
}  // namespace softwrist::cli
