// `softwrist synthesize`, `import` and `diagnose` from the command line: a small synthesized data set with a CSV of
// the user's own beside it goes through to diagnosis.json, and each bad argument or input gives `error: ...` naming
// it (the diagnosis itself is tested in tests/diagnosis/diagnosis_test.cc).

#include <filesystem>
#include <fstream>
#include <set>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/run_cli_for_test.h"
#include "diagnosis_bench/independent_benchmark.h"
#include "support/end_to_end_test.h"
#include "support/scratch_dir_test.h"

namespace softwrist::cli {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
const fs::path kSource = SOFTWRIST_SOURCE_DIR;

using CliDiagnose = softwrist::testing::ScratchDirTest;

TEST_F(CliDiagnose, SynthesizeImportAndDiagnoseWriteTheReport) {
  const std::string model = (kSource / "models/paper_device.json").string();
  const auto synth = run({"synthesize", "--model", model, "--out", (dir_ / "real").string(), "--trajectory-s", "4",
                          "--repetitions", "2", "--imu-offset-deg", "1.5,0"});
  ASSERT_EQ(synth.code, 0) << synth.err;
  EXPECT_TRUE(fs::exists(dir_ / "real/real_device.json"));
  // The user's own range-of-motion measurements, imported beside the synthesized logs.
  std::ofstream(dir_ / "rom.csv") << "muscle,pressure_kpa,limit_deg\nflexor,137,25\nextensor,137,50\n";
  const auto imported =
      run({"import", (dir_ / "rom.csv").string(), "--kind", "rom", "--out", (dir_ / "real/mine").string()});
  ASSERT_EQ(imported.code, 0) << imported.err;
  EXPECT_THAT(imported.out, HasSubstr("(2 rows)"));

  const auto d = run({"diagnose", "--real", (dir_ / "real").string(), "--model", model, "--effects",
                      "imu_bias,passive_wrist", "--bootstrap", "20", "--no-plots", "--out", (dir_ / "diag").string()});
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_THAT(d.out, HasSubstr("verdict: "));
  const auto json = nlohmann::json::parse(std::ifstream(dir_ / "diag/diagnosis.json"));
  ASSERT_EQ(json["effects"].size(), 2u);
  for (const char* key : {"verdict", "effects", "localization", "error_metric"}) EXPECT_TRUE(json.contains(key)) << key;
  std::set<std::string> experiments;
  for (const auto& t : json["trials"]) experiments.insert(t["experiment"].get<std::string>());
  EXPECT_TRUE(experiments.contains("mine/trials")) << json["trials"].dump();
  EXPECT_TRUE(experiments.contains("trajectory/trials:case 0 pressures")) << json["trials"].dump();
  // The gap closed is printed only where some trial had a gap to close.
  bool any_gap = false;
  for (const auto& t : json["trials"]) any_gap = any_gap || t["gap"].get<bool>();
  EXPECT_THAT(d.out, HasSubstr(any_gap ? "the same over the trials with a significant gap" : "nothing to close"));
  EXPECT_TRUE(fs::exists(dir_ / "diag/diagnosis.html"));
}

const std::string torque_rig = (kSource / "experiments/independent_device/torque_rig.json").string();
const std::string prototype = (kSource / "experiments/independent_device/prototype.json").string();

TEST_F(CliDiagnose, BadArgumentsAndInputsNameTheProblem) {
  const std::string model = (kSource / "models/paper_device.json").string();
  const std::string empty = (dir_ / "empty").string();
  fs::create_directories(empty);
  struct Case {
    std::vector<std::string> args;
    int code;  // 1 bad input, 2 bad arguments (cli.cc); 0: CLI11's own code for a missing option
    std::string says;
  };
  const std::vector<Case> cases = {
      {{"diagnose", "--real", (dir_ / "nowhere").string(), "--model", model}, 1, "not a directory of trial logs"},
      {{"diagnose", "--real", empty, "--model", model}, 1, "no trial logs found"},
      {{"diagnose", "--real", empty, "--model", model, "--effects", "friction"},
       2,
       "'friction' is not in the catalogue"},
      {{"diagnose", "--real", empty, "--model", (dir_ / "none.json").string()}, 1, "none.json"},
      {{"diagnose", "--real", empty, "--model", model, "--bootstrap", "3"}, 2, "--bootstrap must be >= 20"},
      {{"diagnose", "--model", model}, 0, "--real is required"},
      {{"import", (dir_ / "x.csv").string(), "--kind", "speed", "--out", empty}, 1, "--kind: 'speed'"},
      {{"import", (dir_ / "missing.csv").string(), "--kind", "rom", "--out", empty}, 1, "missing.csv"},
      {{"synthesize", "--model", model, "--out", empty, "--dead-time-s", "2"}, 2, "--dead-time-s must be within 0..1"},
      {{"synthesize", "--model", model, "--out", empty, "--imu-offset-deg", "1"}, 2, "--imu-offset-deg"},
      {{"synthesize", "--model", model, "--out", empty, "--eps-max-shift", "0.9"}, 2, "max_contraction eps_max"},
      {{"generate", "--out", empty, "--effect", "nonsense"}, 2, "unknown effect form 'nonsense'"},
      {{"generate", "--out", empty, "--effect", "slow_vent:2"}, 2, "level 2 is outside (0, 1]"},
      {{"generate", "--out", empty, "--effect", "slow_vent:abc"},
       2,
       "--effect 'slow_vent:abc' level: 'abc' is not a finite number"},
      {{"generate"}, 2, "--out is required"},
      {{"diagnose", "--real", empty, "--model", model, "--tolerances", (dir_ / "tol.json").string()},
       1,
       "tol.json: r0_fractoin: unknown field"},
      {{"diagnose", "--real", empty, "--model", model, "--tolerances", (dir_ / "tol.json").string(), "--no-tolerances"},
       2,
       "exclude each other"},
      {{"diagnose", "--real", empty, "--model", model, "--no-tolerances", "--rank-beyond-tolerances"},
       2,
       "--rank-beyond-tolerances needs the tolerances"},
      {{"diagnose", "--real", empty, "--model", model, "--no-tolerances", "--effect-base", "within-tolerances"},
       2,
       "--effect-base within-tolerances needs the tolerances"},
      {{"diagnose-bench", "--effect-base", "halfway"}, 2, "--effect-base: 'halfway' is none of better"},
      {{"diagnose-bench", "--generator", "mirror"}, 2, "'mirror' is neither catalogue nor independent"},
      {{"diagnose-bench", "--shard", "1/2"}, 2, "--shard needs --generator independent"},
      {{"diagnose-bench", "--calibrate", empty}, 2, "--calibrate needs --generator independent"},
      {{"diagnose-bench", "--rank-beyond-tolerances"}, 2, "--rank-beyond-tolerances needs --generator independent"},
      {{"diagnose-bench", "--repeat-mean-test"}, 2, "--repeat-mean-test needs --generator independent"},
      {{"diagnose-bench", "--routing-by", "best"}, 2, "--routing-by needs --generator independent"},
      {{"diagnose", "--real", empty, "--model", model, "--routing-by", "luck"},
       2,
       "--routing-by: 'luck' is neither best nor nominal"},
      {{"diagnose-bench", "--generator", "independent", "--redecide"}, 2, "--redecide needs --merge"},
      {{"diagnose-bench", "--generator", "independent", "--variation", "2"}, 2, "--variation is the catalogue"},
      {{"diagnose-bench", "--generator", "independent", "--forms", "nonsense", "--prototype", prototype, "--torque-rig",
        torque_rig},
       2,
       "'nonsense' is not a form"},
      {{"diagnose-bench", "--generator", "independent", "--shard", "3/2", "--prototype", prototype, "--torque-rig",
        torque_rig},
       2,
       "--shard"},
      {{"diagnose-bench", "--generator", "independent", "--prototype", (dir_ / "nowhere.json").string()},
       2,
       "no placement file"},
      {{"diagnose-bench", "--generator", "independent", "--merge", (dir_ / "missing.json").string()},
       1,
       "missing.json"},
  };
  std::ofstream(dir_ / "x.csv") << "muscle,pressure_kpa,limit_deg\nflexor,137,25\n";
  std::ofstream(dir_ / "tol.json") << R"({"r0_fractoin": 0.05})";
  for (const Case& c : cases) {
    const auto r = run(c.args);
    EXPECT_NE(r.code, 0) << c.says;
    if (c.code != 0) {
      EXPECT_EQ(r.code, c.code) << c.args[0] << " " << c.says << ": " << r.err;
      EXPECT_THAT(r.err, HasSubstr("error: ")) << c.says;
    }
    EXPECT_THAT(r.err, HasSubstr(c.says));
  }
}

// `softwrist generate`: the independent device's data set, with the manifest a user imports by and the truth.
TEST_F(CliDiagnose, GenerateWritesTheIndependentDevicesDataSet) {
  const auto r = run({"generate", "--out", (dir_ / "data").string(), "--seed", "2", "--effect", "slow_vent:0.5",
                      "--trajectory-s", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("labels regulator_lag"));
  const auto manifest = nlohmann::json::parse(std::ifstream(dir_ / "data/manifest.json"));
  for (const auto& file : manifest.at("files"))
    EXPECT_TRUE(fs::exists(dir_ / "data" / file.at("csv").get<std::string>()));
  const auto truth = nlohmann::json::parse(std::ifstream(dir_ / "data/truth.json"));
  EXPECT_EQ(truth.at("effects").at(0).at("form"), "slow_vent");
  const auto forms = run({"generate", "--list-forms"});
  ASSERT_EQ(forms.code, 0) << forms.err;
  EXPECT_THAT(forms.out, HasSubstr("leaking_fitting"));
}

// diagnose-bench on the independent device, end to end: the nominal device at seed 14, run as shard 1 of 2 (shard 2
// is empty) and merged; the run is scored and nothing failed. (That merged shards give the same figures as one run
// is tested on the runs themselves, independent_benchmark_test: a diagnosis of this data set takes minutes.)
//
// The same run's kept diagnosis: the routing is chosen by how each routing's models predict the held-out part, not by
// how they fit the training part (docs/diagnosis.md, "Routing"). On this data set (the independent device's nominal,
// routed planar) the spatial run's corrected model, a mount stretch on top, once fitted the training part as well as
// the planar nominal within its tolerances (0.840 against 0.848), was kept, and the data set read `unexplained`. Each
// routing's nominal within its tolerances alone tells them apart too.
// (One diagnosis for both checks: each took over three minutes of CI's test stage as a test of its own. Trajectories
// of 8 s instead of the benchmark's 12: 220 s of CPU against 281 s, the routing as clear, planar 0.086 against spatial
// 0.380.)
TEST_F(CliDiagnose, IndependentBenchmarkRunsShardsMergesAndChoosesTheRoutingOnTheHeldOutPart) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const std::vector<std::string> bench = {"diagnose-bench", "--generator", "independent",    "--forms",
                                          "none",           "--no-pairs",  "--seeds",        "1",
                                          "--first-seed",   "14",          "--trajectory-s", "8",
                                          "--prototype",    prototype,     "--torque-rig",   torque_rig,
                                          "--jobs",         "1",           "--keep",         (dir_ / "kept").string()};
  for (const char* shard : {"1/2", "2/2"}) {
    std::vector<std::string> args = bench;
    for (const std::string& more : {std::string("--shard"), std::string(shard), std::string("--out"),
                                    (dir_ / (std::string("shard") + shard[0] + ".json")).string()})
      args.push_back(more);
    const auto r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("'none' on the nominal device"));
  }
  const auto d = nlohmann::json::parse(std::ifstream(dir_ / "kept/none-14/diagnosis.json"));
  ASSERT_TRUE(d["routing"].contains("heldout_error_best")) << d["routing"].dump();
  EXPECT_EQ(d["routing"]["used"], "planar");
  EXPECT_LT(d["routing"]["heldout_error_best"]["planar"].get<double>(),
            0.5 * d["routing"]["heldout_error_best"]["spatial"].get<double>());
  const auto& within = d["routing"]["heldout_error_nominal_within_tolerances"];
  ASSERT_TRUE(within.is_object()) << d["routing"].dump();
  EXPECT_LT(within["planar"].get<double>(), 0.5 * within["spatial"].get<double>()) << d["routing"].dump();
  EXPECT_EQ(d["verdict"], "none") << d["reason"];

  const auto merged = run({"diagnose-bench", "--generator", "independent", "--json", "--merge",
                           (dir_ / "shard1.json").string(), (dir_ / "shard2.json").string()});
  ASSERT_EQ(merged.code, 0) << merged.err;
  const auto summary = nlohmann::json::parse(merged.out);
  ASSERT_EQ(summary["runs"].size(), 1u);
  EXPECT_EQ(summary["runs"][0]["error"], "") << summary["runs"][0].dump();
  EXPECT_EQ(summary["runs"][0]["expected"], "none");
  EXPECT_EQ(summary["counts"]["none"]["cases"], 1);
  for (const char* key : {"top1_ci95", "none_correct_rate_ci95", "unexplained_correct_rate_ci95",
                          "pairs_primary_correct_rate", "detection_curve"})
    EXPECT_TRUE(summary.contains(key)) << key;
  // The run was decided on the grid of settings too; the calibration from it keeps the settings this build uses,
  // every one of which names the nominal device `none`.
  EXPECT_EQ(summary["runs"][0]["by_setting"].size(), diagnosis_bench::decision_grid().size());
  const auto calibrated = run({"diagnose-bench", "--generator", "independent", "--merge",
                               (dir_ / "shard1.json").string(), "--calibrate", (dir_ / "calibration.json").string()});
  ASSERT_EQ(calibrated.code, 0) << calibrated.err;
  const auto record = nlohmann::json::parse(std::ifstream(dir_ / "calibration.json"));
  EXPECT_EQ(record["chosen"]["none"], 1.0);
  EXPECT_EQ(record["chosen"]["explained_fraction"], record["current"]["explained_fraction"]);
  const auto redecided = run({"diagnose-bench", "--generator", "independent", "--json", "--merge",
                              (dir_ / "shard1.json").string(), "--redecide"});
  ASSERT_EQ(redecided.code, 0) << redecided.err;
  EXPECT_EQ(nlohmann::json::parse(redecided.out)["runs"][0]["verdict"], summary["runs"][0]["verdict"]);
  const auto twice = run({"diagnose-bench", "--generator", "independent", "--merge", (dir_ / "shard1.json").string(),
                          (dir_ / "shard1.json").string()});
  EXPECT_EQ(twice.code, 2);
  EXPECT_THAT(twice.err, HasSubstr("appears twice"));
  // Runs of another seed (the same index) merge beside it: a calibration over several reported seeds.
  auto other_seed = nlohmann::json::parse(std::ifstream(dir_ / "shard1.json"));
  for (auto& r : other_seed["runs"]) r["seed"] = r["seed"].get<int>() + 1;
  std::ofstream(dir_ / "other_seed.json") << other_seed.dump();
  const auto two_seeds = run({"diagnose-bench", "--generator", "independent", "--json", "--merge",
                              (dir_ / "shard1.json").string(), (dir_ / "other_seed.json").string()});
  ASSERT_EQ(two_seeds.code, 0) << two_seeds.err;
  EXPECT_EQ(nlohmann::json::parse(two_seeds.out)["counts"]["none"]["cases"], 2);
}

}  // namespace
}  // namespace softwrist::cli
