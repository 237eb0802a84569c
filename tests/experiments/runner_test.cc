// The runner: the same seed gives the same log for any number of threads; shards merged equal the single run;
// bad configs and incomplete merges are rejected with messages naming the file and the field.

#include "experiments/runner.h"

#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "io/text_file.h"

#include "support/scratch_dir_test.h"

namespace softwrist::experiments {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kSource = SOFTWRIST_SOURCE_DIR;

class RunnerTest : public softwrist::testing::ScratchDirTest {
 protected:
  // A small torque validation: 3 angles x 2 pressures x 2 repetitions.
  ExperimentConfig config(const std::string& extra = "") {
    const fs::path path = dir_ / "small.json";
    std::ofstream(path) << R"({"format": "softwrist.experiment/1", "kind": "torque_validation", "model": ")"
                        << (kSource / "models/paper_device.json").string()
                        << R"(", "angles_deg": [-45, 0, 45], "pressures_kpa": [68, 137], "repetitions": 2,
                              "seed": 7, "hold_time_s": 0.5)"
                        << extra << "}";
    return load_experiment_config(path);
  }
  std::string error_of(const std::string& text) {
    const fs::path path = dir_ / "bad.json";
    std::ofstream(path) << text;
    try {
      (void)make_experiment(load_experiment_config(path));
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(RunnerTest, SameSeedSameNumbersForAnyThreadCount) {
  const auto one = run_experiment(config(), {.out = dir_ / "one", .jobs = 1});
  const auto two = run_experiment(config(), {.out = dir_ / "two", .jobs = 2});
  EXPECT_TRUE(one.complete);
  EXPECT_EQ(one.cases_run, 12);
  EXPECT_EQ(io::read_text_file(dir_ / "one/trials.csv"), io::read_text_file(dir_ / "two/trials.csv"));
  EXPECT_EQ(one.summary, two.summary);
  // Another seed gives other noise.
  const auto other = run_experiment(config(R"(, "sensor_noise": {"torque_std_nm": 0.02})"), {.out = dir_ / "three"});
  EXPECT_NE(io::read_text_file(dir_ / "one/trials.csv"), io::read_text_file(dir_ / "three/trials.csv"));
  (void)other;
}

TEST_F(RunnerTest, ShardsMergeToTheSingleRun) {
  run_experiment(config(), {.out = dir_ / "whole", .jobs = 2});
  std::vector<fs::path> shards;
  for (int k = 1; k <= 3; ++k) {
    shards.push_back(dir_ / ("shard" + std::to_string(k)));
    const auto r = run_experiment(config(), {.out = shards.back(), .shard_index = k, .shard_count = 3});
    EXPECT_FALSE(r.complete);
    EXPECT_EQ(r.cases_run, 4);
    EXPECT_FALSE(fs::exists(shards.back() / "summary.json"));
  }
  const auto merged = merge_runs({shards[2], shards[0], shards[1]}, dir_ / "merged");
  EXPECT_TRUE(merged.complete);
  EXPECT_EQ(io::read_text_file(dir_ / "whole/trials.csv"), io::read_text_file(dir_ / "merged/trials.csv"));
  EXPECT_EQ(io::read_text_file(dir_ / "whole/summary.json"), io::read_text_file(dir_ / "merged/summary.json"));

  try {
    merge_runs({shards[0], shards[2]}, dir_ / "incomplete");
    ADD_FAILURE() << "merged without shard 2";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cases missing (first ones: 1, 4, 7, 10)"));
  }
  try {
    merge_runs({shards[0], shards[0], shards[1], shards[2]}, dir_ / "twice");
    ADD_FAILURE() << "merged a shard twice";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("case 0 is also in"));
  }
  run_experiment(config(R"(, "sensor_noise": {"torque_std_nm": 0.5})"),
                 {.out = dir_ / "other", .shard_index = 2, .shard_count = 3});
  try {
    merge_runs({shards[0], dir_ / "other", shards[2]}, dir_ / "mixed");
    ADD_FAILURE() << "merged shards of two configs";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("another experiment config"));
  }
}

TEST_F(RunnerTest, TheLogIsTheDocumentedFormat) {
  run_experiment(config(), {.out = dir_ / "run"});
  const TrialLog log = read_log(dir_ / "run", kTrialLogName);
  EXPECT_EQ(log.header.kind, "torque_validation");
  EXPECT_EQ(log.header.case_count, 12);
  EXPECT_EQ(log.header.columns.front().name, "case");
  EXPECT_EQ(log.table.row_count(), 12u);
  EXPECT_THAT(log.header.model_hash, HasSubstr("fnv1a64:"));
  const auto sidecar = nlohmann::json::parse(io::read_text_file(dir_ / "run/trials.json"));
  EXPECT_EQ(sidecar["format"], "softwrist.log/1");
  EXPECT_TRUE(sidecar.contains("software_version"));
  for (const auto& column : sidecar["columns"]) EXPECT_TRUE(column.contains("unit")) << column.dump();
}

TEST_F(RunnerTest, BadConfigsNameTheFileAndTheField) {
  const std::string model = (kSource / "models/paper_device.json").string();
  EXPECT_THAT(error_of("{"), HasSubstr("bad.json: not valid JSON"));
  EXPECT_THAT(error_of(R"({"format": "softwrist.experiment/1"})"), HasSubstr("bad.json: kind: missing"));
  EXPECT_THAT(error_of(R"({"format": "softwrist.experiment/1", "kind": "juggling"})"),
              HasSubstr("bad.json: kind: 'juggling' is not"));
  EXPECT_THAT(error_of(R"({"format": "softwrist.experiment/1", "kind": "torque_validation"})"),
              HasSubstr("bad.json: model: missing"));
  EXPECT_THAT(error_of(R"({"format": "softwrist.experiment/1", "kind": "torque_validation", "model": "nope.json"})"),
              HasSubstr("bad.json: model: no such file"));
  const std::string head =
      R"({"format": "softwrist.experiment/1", "kind": "torque_validation", "model": ")" + model + "\", ";
  EXPECT_THAT(error_of(head + R"("pressures_kpa": [68, 500]})"), HasSubstr("bad.json: pressures_kpa: 500 is outside"));
  EXPECT_THAT(error_of(head + R"("pressures_kpa": [68, "x"]})"),
              HasSubstr("bad.json: pressures_kpa[1]: must be a finite number"));
  EXPECT_THAT(error_of(head + R"("repetitons": 3})"), HasSubstr("bad.json: repetitons: unknown field"));
  EXPECT_THAT(error_of(head + R"("sensor_noise": {"torque_std_nm": -1}})"),
              HasSubstr("bad.json: sensor_noise.torque_std_nm: must be >= 0"));
  EXPECT_THAT(error_of(head + R"("muscle": "biceps"})"), HasSubstr("bad.json: muscle: 'biceps'"));
  const std::string design = R"({"format": "softwrist.experiment/1", "kind": "design_optimization", "reference": ")" +
                             (kSource / "experiments/reference/flexion_torque_example.csv").string() + "\", ";
  EXPECT_THAT(error_of(design + "\"samples\": 140}"), HasSubstr("bad.json: max_stretch_angle_deg: missing"));
  EXPECT_THAT(error_of(design + R"("max_stretch_angle_deg": -65.4, "algorithm": "simplex"})"),
              HasSubstr("bad.json: (top level): unknown optimizer algorithm 'simplex'"));
  EXPECT_THAT(
      error_of(
          design +
          R"("max_stretch_angle_deg": -65.4, "bounds_cm": {"lower": {"d1": 2, "w1": 3.5, "d2": 1.5}, "upper": {"d1": 22, "w1": 5, "d2": 9, "w2": 3.5}}})"),
      HasSubstr("bad.json: bounds_cm.lower.w2: missing"));
  std::ofstream(dir_ / "bad_reference.csv") << "angle_deg,torque_nm\n0,1\n10,oops\n";
  const std::string bad_reference =
      R"({"format": "softwrist.experiment/1", "kind": "design_optimization", "reference": "bad_reference.csv", "max_stretch_angle_deg": -65.4})";
  EXPECT_THAT(error_of(bad_reference), HasSubstr("bad_reference.csv:3: torque_nm: not a number: 'oops'"));
  const std::string tracking =
      R"({"format": "softwrist.experiment/1", "kind": "tracking", "model": ")" + model + "\", ";
  const std::string steps = R"("trajectory": {"type": "steps", "levels_fe_deg": [0, 10]}, )";
  EXPECT_THAT(error_of(tracking + R"("controllers": [{"name": "paper"}]})"),
              HasSubstr("bad.json: trajectory: missing"));
  EXPECT_THAT(error_of(tracking + R"("trajectory": {"type": "zigzag"}, "controllers": [{"name": "paper"}]})"),
              HasSubstr("bad.json: trajectory.type: 'zigzag' is not steps or sinusoid"));
  EXPECT_THAT(error_of(tracking +
                       R"("trajectory": {"type": "sinusoid", "fe_min_deg": 40}, "controllers": [{"name": "paper"}]})"),
              HasSubstr("bad.json: trajectory.fe_min_deg: is above fe_max_deg"));
  EXPECT_THAT(error_of(tracking + steps + R"("controllers": [{"name": "bang_bang"}]})"),
              HasSubstr("bad.json: controllers[0].name: 'bang_bang' is not paper, model_based or excitation"));
  EXPECT_THAT(error_of(tracking + steps + R"("controllers": [{"name": "excitation"}]})"),
              HasSubstr("bad.json: trajectory: an excitation routine sets its own length; leave it out"));
  EXPECT_THAT(error_of(tracking + R"("controllers": [{"name": "paper"}, {"name": "excitation"}]})"),
              HasSubstr("bad.json: controllers[1].name: the excitation routine runs alone"));
  EXPECT_THAT(error_of(tracking + R"("controllers": [{"name": "excitation", "step_levels_kpa": [45, 200]}]})"),
              HasSubstr("bad.json: controllers[0].step_levels_kpa: 200 kPa is outside 0..137 kPa"));
  EXPECT_THAT(error_of(tracking + steps + R"("controllers": [{"name": "paper"}, {"name": "paper"}]})"),
              HasSubstr("bad.json: controllers[1].name: 'paper' is listed twice"));
  EXPECT_THAT(error_of(tracking + steps + R"("controllers": [{"name": "model_based", "kp_nm_per_rad": -1}]})"),
              HasSubstr("bad.json: controllers[0].kp_nm_per_rad: must be >= 0"));
  EXPECT_THAT(error_of(tracking + steps + R"("controllers": [{"name": "model_based", "co_contraction_kpa": 150}]})"),
              HasSubstr("bad.json: controllers[0].co_contraction_kpa: must be below the regulator's maximum"));
  EXPECT_THAT(error_of(tracking + steps + R"("controllers": [{"name": "paper", "initial_kpa": 140}]})"),
              HasSubstr("bad.json: controllers[0].initial_kpa: is above the regulator's 137 kPa"));
  EXPECT_THAT(error_of(tracking + steps + R"("pairs": ["fe", "pronation"], "controllers": [{"name": "paper"}]})"),
              HasSubstr("bad.json: pairs: \"pronation\" is not"));
  EXPECT_THAT(error_of(tracking + steps + R"("controllers": []})"),
              HasSubstr("bad.json: controllers: must be a non-empty list"));
}

TEST(ParseShard, AcceptsKOfNOnly) {
  EXPECT_EQ(parse_shard("2/5"), std::make_pair(2, 5));
  for (const char* bad : {"0/3", "4/3", "1/0", "a/b", "1/2x", "1"})
    EXPECT_THROW(parse_shard(bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace softwrist::experiments
