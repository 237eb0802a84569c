// The paper's experiments in simulation, checked against the analytic model (src/physics) they must agree with.

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include "experiments/runner.h"
#include "io/json_reader.h"
#include "io/text_file.h"

namespace softwrist::experiments {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = SOFTWRIST_SOURCE_DIR;

nlohmann::json run(const std::string& name, const std::string& body) {
  const fs::path dir = fs::temp_directory_path() / ("softwrist_experiments_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "config.json") << body;
  const auto result = run_experiment(load_experiment_config(dir / "config.json"), {.out = dir / "run", .jobs = 2});
  fs::remove_all(dir);
  return result.summary;
}

// Table RoM in simulation: each muscle's settled angle agrees with the analytic statics (muscle with stretching,
// deflated antagonist, relaxed-wrist stiffness, hand weight, joint stop) within 1.5 deg, and lies below the
// paper's modeled limit (torque zero, no stretching), which ignores those effects.
TEST(RangeOfMotionExperiment, SettledAnglesAgreeWithTheAnalyticStatics) {
  const auto summary = run("rom", R"({"format": "softwrist.experiment/1", "kind": "range_of_motion", "model": ")" +
                                      (kSource / "models/rom_device.json").string() +
                                      R"(", "repetitions": 1, "sensor_noise": {"angle_std_deg": 0}})");
  ASSERT_EQ(summary["muscles"].size(), 4u);
  for (const auto& m : summary["muscles"]) {
    const double settled = m["settled_deg"];
    EXPECT_NEAR(settled, m["analytic_settled_deg"].get<double>(), 1.5) << m["muscle"];
    EXPECT_LT(settled, m["analytic_limit_deg"].get<double>()) << m["muscle"];
    EXPECT_GT(settled, 5.0) << m["muscle"];
  }
}

// Fig. ExperimentalData in simulation, without noise: the self-consistent stretching model is the simulated
// device's own law, so it agrees best; the paper's one-shot stretching comes next; ignoring stretching is worst
// (the paper's ordering, 0.283 < 1.111 N m). With exact markers the motion-capture placement gives the
// self-consistent torque too (the stretched mounts stay on the line of action).
TEST(TorqueValidationExperiment, StretchingMethodsOrderAsInThePaper) {
  const auto summary = run(
      "torque",
      R"({"format": "softwrist.experiment/1", "kind": "torque_validation", "model": ")" +
          (kSource / "models/paper_device.json").string() +
          R"(", "repetitions": 1, "sensor_noise": {"torque_std_nm": 0, "angle_jitter_deg": 0, "marker_std_mm": 0}})");
  const auto& mae = summary["mae_nm"];
  EXPECT_LT(mae["fixed_stretch_selfconsistent"].get<double>(), 0.03);
  EXPECT_LT(mae["motion_capture"].get<double>(), 0.03);
  EXPECT_LT(mae["fixed_stretch_selfconsistent"].get<double>(), mae["fixed_stretch"].get<double>());
  EXPECT_LT(2.0 * mae["fixed_stretch"].get<double>(), mae["fixed_no_stretch"].get<double>());
  EXPECT_EQ(summary["groups"].size(), 40u);
}

// A shipped config with its model path made absolute and fewer repetitions.
std::string shipped_config(const std::string& name, int repetitions) {
  nlohmann::json config = io::parse_json(io::read_text_file(kSource / "experiments" / name), name);
  config["model"] = (kSource / "experiments" / config["model"].get<std::string>()).lexically_normal().string();
  config["repetitions"] = repetitions;
  return config.dump();
}

// Section Planar angle tracking in simulation, both controllers: every step whose target the exosuit can hold
// (physics::reachable_range) is reached; the 30 and 40 deg flexion targets lie beyond the simulated device's
// flexion range (27.5 deg, Table RoM device) and are not reached, and the model-based controller reports them. No
// command leaves the regulator range. The model-based controller meets its targets: overshoot under 10 % and rise
// times under the paper's 0.84 s.
TEST(TrackingExperiment, PlanarStepsReachEveryTargetInRangeAndReportTheOthers) {
  const auto summary = run("planar", shipped_config("planar_tracking.json", 1));
  ASSERT_EQ(summary["controllers"].size(), 2u);
  for (const auto& c : summary["controllers"]) {
    const std::string name = c["controller"];
    EXPECT_LE(c["max_command_kpa"].get<double>(), 137.0) << name;
    int beyond = 0;
    for (const auto& step : c["steps"]) {
      if (step["within_model_reach"].get<bool>()) {
        EXPECT_TRUE(step["reached"].get<bool>()) << name << " " << step.dump();
      } else {
        ++beyond;
        EXPECT_FALSE(step["reached"].get<bool>()) << name << " " << step.dump();
        if (name == "model_based") {
          EXPECT_TRUE(step["reported_unreachable"].get<bool>()) << step.dump();
        }
      }
    }
    EXPECT_EQ(beyond, 2) << name;
    if (name == "model_based") {
      for (const char* direction : {"towards_extension", "towards_flexion"}) {
        EXPECT_LT(c[direction]["overshoot_pct"].get<double>(), 10.0) << direction;
        EXPECT_LT(c[direction]["rise_time_s"].get<double>(), 0.84) << direction;
      }
    }
  }
}

// Section Spatial trajectory tracking in simulation: where the targets are reachable the model-based controller
// stays within 2 deg RMSE on both axes (the issue's target) and beats the paper's controller; on the whole
// trajectory neither beats the floor set by the device's reach (the ulnar targets above its ulnar range).
TEST(TrackingExperiment, SpatialTrackingWithinTwoDegreesWhereReachable) {
  const auto summary = run("spatial", shipped_config("spatial_tracking.json", 1));
  const auto& floor = summary["reach_limited_rmse_floor_deg"];
  std::map<std::string, nlohmann::json> by_name;
  for (const auto& c : summary["controllers"]) by_name[c["controller"]] = c;
  ASSERT_TRUE(by_name.contains("paper") && by_name.contains("model_based"));
  for (const char* axis : {"fe", "ur"}) {
    const std::string reachable = std::string("reachable_rmse_") + axis + "_deg";
    const std::string whole = std::string("rmse_") + axis + "_deg";
    EXPECT_LT(by_name["model_based"][reachable].get<double>(), 2.0) << axis;
    EXPECT_LT(by_name["model_based"][reachable].get<double>(), by_name["paper"][reachable].get<double>()) << axis;
    for (const auto& [name, c] : by_name) EXPECT_GE(c[whole].get<double>(), floor[axis].get<double>()) << name;
  }
  EXPECT_GT(floor["ur"].get<double>(), 1.0);  // the ulnar range is short of the 30 deg targets
}

}  // namespace
}  // namespace softwrist::experiments
