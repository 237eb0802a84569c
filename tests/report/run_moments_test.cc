// The moments of a run (report/run_moments.h), the renders and the video of them (pose_renderer.h,
// video_writer.h), on small trial logs written here so that every expected pose is known.

#include "report/run_moments.h"

#include <cmath>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "experiments/trial_log.h"
#include "io/subprocess.h"
#include "io/text_file.h"
#include "physics/units.h"
#include "report/pose_renderer.h"
#include "report/video_writer.h"
#include "support/scratch_dir_test.h"

namespace softwrist::report {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;
using units::deg_to_rad;

class RunMomentsTest : public testing::ScratchDirTest {
 protected:
  // Writes <dir_>/<name>/trials.{json,csv} of `kind` with these columns and rows (no model: the paper's device).
  fs::path write_run(const std::string& name, const std::string& kind, const std::vector<std::string>& columns,
                     const std::vector<std::vector<std::string>>& rows) {
    experiments::LogHeader header{.kind = kind, .config = {{"kind", kind}}, .config_dir = dir_.string()};
    for (const std::string& c : columns) header.columns.push_back({c, "", ""});
    header.case_count = static_cast<int>(rows.size());
    experiments::LogWriter log(dir_ / name, "trials", header);
    for (const auto& row : rows) log.write_row(row);
    return dir_ / name;
  }

  // A tracking log: case 0 (paper, fe only) flexes to 20 deg at t = 0.02 and extends to -15 deg at t = 0.03;
  // case 1 (model_based) also moves ulnar/radial.
  fs::path tracking_run() {
    const std::vector<std::string> columns = {"case",          "repetition",    "controller",     "t_s",
                                              "true_fe_deg",   "true_ur_deg",   "cmd_flexor_kpa", "cmd_extensor_kpa",
                                              "cmd_ulnar_kpa", "cmd_radial_kpa"};
    return write_run("tracking", "tracking", columns,
                     {{"0", "0", "paper", "0", "0", "0", "13.8", "13.8", "0", "0"},
                      {"0", "0", "paper", "0.01", "5", "0.5", "40", "0", "0", "0"},
                      {"0", "0", "paper", "0.02", "20", "1", "60", "0", "0", "0"},
                      {"0", "0", "paper", "0.03", "-15", "-1", "0", "70", "0", "0"},
                      {"1", "2", "model_based", "0", "0", "0", "5", "5", "5", "5"},
                      {"1", "2", "model_based", "0.01", "3", "12", "20", "5", "80", "0"},
                      {"1", "2", "model_based", "0.02", "-4", "-9", "5", "30", "0", "90"}});
  }
};

// Range of motion: each muscle's first repetition, the settled angle signed by the muscle's direction (the log
// holds it in the muscle's own direction), on the camera of its axis.
TEST_F(RunMomentsTest, RangeOfMotionDrawsEachMuscleSettledAtItsPressure) {
  const fs::path run = write_run("rom", "range_of_motion",
                                 {"case", "repetition", "muscle", "pressure_kpa", "limit_deg", "other_angle_deg"},
                                 {{"0", "0", "flexor", "137", "27.5", "15"},
                                  {"1", "1", "flexor", "137", "28", "14"},
                                  {"2", "0", "radial", "100", "23", "-6"}});
  const RunMoments m = run_moments(run);
  ASSERT_EQ(m.moments.size(), 2u);
  EXPECT_EQ(m.moments[0].name, "rom_flexor");
  EXPECT_DOUBLE_EQ(m.moments[0].pose.fe, deg_to_rad(27.5));
  EXPECT_DOUBLE_EQ(m.moments[0].pose.ur, deg_to_rad(15));
  EXPECT_EQ(m.moments[0].pose.pressures_kpa, (std::array<double, 4>{137, 0, 0, 0}));
  EXPECT_EQ(m.moments[0].view, View::kRadial);
  EXPECT_EQ(m.moments[1].name, "rom_radial");
  EXPECT_DOUBLE_EQ(m.moments[1].pose.ur, deg_to_rad(-23));
  EXPECT_DOUBLE_EQ(m.moments[1].pose.fe, deg_to_rad(-6));
  EXPECT_EQ(m.moments[1].pose.pressures_kpa, (std::array<double, 4>{0, 0, 0, 100}));
  EXPECT_EQ(m.moments[1].view, View::kPalmar);
  EXPECT_THAT(m.moments[1].caption, HasSubstr("radial alone at 100 kPa"));
}

// Tracking: the extremes of the chosen case on the axes it moves, or the logged instant nearest --at.
TEST_F(RunMomentsTest, TrackingDrawsTheExtremesOrTheNearestInstant) {
  const fs::path run = tracking_run();
  const RunMoments fe_only = run_moments(run);
  ASSERT_EQ(fe_only.moments.size(), 2u);  // case 0 never pressurizes the ulnar/radial pair
  EXPECT_EQ(fe_only.moments[0].name, "case0_most_flexed");
  EXPECT_DOUBLE_EQ(fe_only.moments[0].pose.fe, deg_to_rad(20));
  EXPECT_EQ(fe_only.moments[0].pose.pressures_kpa[0], 60);
  EXPECT_EQ(fe_only.moments[1].name, "case0_most_extended");
  EXPECT_DOUBLE_EQ(fe_only.moments[1].pose.fe, deg_to_rad(-15));
  EXPECT_THAT(fe_only.moments[1].caption, HasSubstr("paper controller, repetition 0, most extended at t = 0.03 s"));

  const RunMoments both = run_moments(run, {.case_index = 1});
  ASSERT_EQ(both.moments.size(), 4u);
  EXPECT_EQ(both.moments[2].name, "case1_most_ulnar");
  EXPECT_DOUBLE_EQ(both.moments[2].pose.ur, deg_to_rad(12));
  EXPECT_EQ(both.moments[2].view, View::kPalmar);
  EXPECT_DOUBLE_EQ(both.moments[3].pose.ur, deg_to_rad(-9));

  const RunMoments at = run_moments(run, {.at_s = 0.012, .case_index = 1});
  ASSERT_EQ(at.moments.size(), 2u);  // both axes move: both cameras
  EXPECT_EQ(at.moments[0].name, "case1_t0.01_radial");
  EXPECT_EQ(at.moments[1].name, "case1_t0.01_palmar");
  EXPECT_DOUBLE_EQ(at.moments[0].pose.fe, deg_to_rad(3));
  EXPECT_EQ(at.moments[0].pose.pressures_kpa, (std::array<double, 4>{20, 5, 80, 0}));

  const auto timeline = tracking_timeline(run, 0);
  ASSERT_EQ(timeline.size(), 4u);
  EXPECT_DOUBLE_EQ(timeline[2].t, 0.02);
}

// A trial of one of a config's controllers (`trial --controller model_based`) holds only that controller's cases: by
// default the log's first case is drawn, whatever its number.
TEST_F(RunMomentsTest, TrackingDefaultsToTheLogsFirstCase) {
  const std::vector<std::string> columns = {"case",          "repetition",    "controller",     "t_s",
                                            "true_fe_deg",   "true_ur_deg",   "cmd_flexor_kpa", "cmd_extensor_kpa",
                                            "cmd_ulnar_kpa", "cmd_radial_kpa"};
  const fs::path run = write_run("only_case_3", "tracking", columns,
                                 {{"3", "0", "model_based", "0", "0", "0", "5", "5", "0", "0"},
                                  {"3", "0", "model_based", "0.01", "8", "0", "30", "5", "0", "0"}});
  const RunMoments m = run_moments(run);
  ASSERT_FALSE(m.moments.empty());
  EXPECT_EQ(m.moments[0].name, "case3_most_flexed");
  EXPECT_EQ(tracking_timeline(run).size(), 2u);
}

TEST_F(RunMomentsTest, BadQueriesAndLogsNameTheProblem) {
  const fs::path run = tracking_run();
  EXPECT_THAT([&] { run_moments(run, {.case_index = 5}); },
              ThrowsMessage<std::runtime_error>(HasSubstr("no rows of case 5")));
  EXPECT_THAT([&] { run_moments(run, {.at_s = 2.0}); },
              ThrowsMessage<std::runtime_error>(HasSubstr("--at 2 s is outside case 0 (0.00 to 0.03 s)")));
  EXPECT_THAT([&] { run_moments(run, {.at_s = std::nan("")}); },
              ThrowsMessage<std::runtime_error>(HasSubstr("outside")));
  const fs::path rom =
      write_run("rom", "range_of_motion", {"case", "repetition", "muscle", "pressure_kpa", "limit_deg"},
                {{"0", "0", "thumb", "137", "27.5"}});
  EXPECT_THAT([&] { run_moments(rom, {.at_s = 1.0}); },
              ThrowsMessage<std::runtime_error>(HasSubstr("--at needs a tracking run")));
  EXPECT_THAT([&] { run_moments(rom); },
              ThrowsMessage<std::runtime_error>(HasSubstr("missing column 'other_angle_deg'")));
  EXPECT_THAT([&] { tracking_timeline(rom, 0); },
              ThrowsMessage<std::runtime_error>(HasSubstr("is a range_of_motion run; a video needs a tracking run")));
  const fs::path design = write_run("design", "design_optimization", {"case"}, {{"0"}});
  EXPECT_TRUE(run_moments(design).moments.empty());
  EXPECT_THAT([&] { run_moments(dir_ / "none"); }, ThrowsMessage<std::runtime_error>(HasSubstr("trials.json")));
}

// The pose renderer refuses what the regulator cannot do, and a flexed pose differs from the neutral one.
TEST_F(RunMomentsTest, PoseRendererChecksPressuresAndDrawsThePose) {
  PoseRenderer renderer(sim::paper_device(), 64, 48);
  EXPECT_THAT(
      [&] {
        renderer.Render({0.0, 0.0, {0, 0, 200, 0}}, View::kRadial);
      },
      ThrowsMessage<std::runtime_error>(HasSubstr("ulnar pressure 200 kPa is outside the regulator's [0, 137] kPa")));
  EXPECT_THAT(
      [&] {
        renderer.Render({std::nan(""), 0.0, {}}, View::kRadial);
      },
      ThrowsMessage<std::runtime_error>(HasSubstr("not finite")));
  const Image neutral = renderer.Render({}, View::kRadial);
  const Image flexed = renderer.Render({deg_to_rad(40), 0.0, {137, 0, 0, 0}}, View::kRadial);
  EXPECT_NE(neutral.rgb, flexed.rgb);
}

// A video of a tracking case: ffmpeg (Debian's, installed by scripts/setup.sh) encodes every frame; ffprobe counts
// them back from the file.
TEST_F(RunMomentsTest, VideoHasEveryFrame) {
  const auto timeline = tracking_timeline(tracking_run(), 0);
  PoseRenderer renderer(sim::paper_device(), 64, 48);
  VideoWriter video(dir_ / "case0.mp4", 64, 48, 10);
  for (const TimedPose& p : timeline) video.add_frame(renderer.Render(p.pose, View::kRadial));
  EXPECT_THROW(video.add_frame(Image{32, 32, std::vector<unsigned char>(32 * 32 * 3)}), std::runtime_error);
  EXPECT_EQ(video.finish(), 4);
  const int code =
      io::run_process({"ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                       "stream=nb_read_frames,width,height", "-of", "csv=p=0", (dir_ / "case0.mp4").string()},
                      {.stdout_file = dir_ / "probe.txt"});
  ASSERT_EQ(code, 0);
  EXPECT_EQ(io::read_text_file(dir_ / "probe.txt"), "64,48,4\n");
  EXPECT_THAT([&] { VideoWriter(dir_ / "odd.mp4", 63, 48, 10); },
              ThrowsMessage<std::runtime_error>(HasSubstr("must be even")));
  EXPECT_THAT([&] { VideoWriter(dir_ / "fast.mp4", 64, 48, 1000); },
              ThrowsMessage<std::runtime_error>(HasSubstr("1..120")));
}

}  // namespace
}  // namespace softwrist::report
