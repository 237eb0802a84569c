#include "cli/render_command.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "cli/arguments.h"
#include "physics/units.h"
#include "report/offscreen_renderer.h"
#include "report/pose_renderer.h"
#include "report/run_moments.h"
#include "report/video_writer.h"
#include "sim/device.h"

namespace softwrist::cli {
namespace {

namespace fs = std::filesystem;

struct RenderOptions {
  // A pose of a device.
  std::string placement;
  double fe_deg = 0.0;
  double ur_deg = 0.0;
  std::string pressures_kpa = "0,0,0,0";
  std::string view = "radial";
  std::string out;
  // Moments of a run, or a video of a tracking run.
  std::string run;
  std::optional<double> at_s;
  int case_index = -1;  // the log's first case
  std::string out_dir;
  std::string video;
  double fps = 25.0;
  double speed = 1.0;
  std::optional<double> from_s, to_s;
  // Both.
  int width = 640;
  int height = 480;
  bool shadows = false;  // and reflections: the look of the viewer, at less than half the frame rate
  report::RenderQuality quality() const { return {.shadows = shadows, .reflections = shadows}; }
};

report::View view_named(const std::string& name) {
  return name == "palmar" ? report::View::kPalmar : report::View::kRadial;
}

void render_pose(const RenderOptions& options, std::ostream& out) {
  if (options.out.empty()) throw UsageError("render: --out PNG is required (or --run RUN_DIR)");
  const sim::DeviceDescription device =
      options.placement.empty() ? sim::paper_device() : sim::load_device(options.placement);
  const auto pressures = parse_numbers(options.pressures_kpa, 4, "--pressures-kpa");
  const double max_kpa = units::pa_to_kpa(device.regulator.max_pressure);
  report::WristPose pose{units::deg_to_rad(options.fe_deg), units::deg_to_rad(options.ur_deg), {}};
  for (std::size_t i = 0; i < 4; ++i) {
    if (!(pressures[i] >= 0.0 && pressures[i] <= max_kpa)) {
      throw UsageError(
          fmt::format("--pressures-kpa: {} is outside the regulator's [0, {}] kPa", pressures[i], max_kpa));
    }
    pose.pressures_kpa[i] = pressures[i];
  }
  report::PoseRenderer renderer(device, options.width, options.height, options.quality());
  report::write_png(renderer.Render(pose, view_named(options.view)), options.out);
  out << fmt::format("Wrote {} ({}x{}, {} view)\n", options.out, options.width, options.height, options.view);
}

void render_moments(const RenderOptions& options, std::ostream& out) {
  const report::RunMoments run =
      report::run_moments(options.run, {.at_s = options.at_s, .case_index = options.case_index});
  if (run.moments.empty()) {
    out << fmt::format("{}: this run holds no wrist pose to render\n", options.run);
    return;
  }
  const fs::path dir = options.out_dir.empty() ? fs::path(options.run) / "renders" : fs::path(options.out_dir);
  fs::create_directories(dir);
  report::PoseRenderer renderer(run.device, options.width, options.height, options.quality());
  for (const report::Moment& moment : run.moments) {
    const fs::path file = dir / (moment.name + ".png");
    report::write_png(renderer.Render(moment.pose, moment.view), file);
    out << fmt::format("Wrote {}: {}\n", file.string(), moment.caption);
  }
}

// A video of one tracking case: at each frame, the last logged pose at or before its time (the log's control
// ticks, 10-14 ms apart, are finer than any frame rate here).
void render_video(const RenderOptions& options, std::ostream& out) {
  const std::vector<report::TimedPose> timeline = report::tracking_timeline(options.run, options.case_index);
  const double from = options.from_s.value_or(timeline.front().t), to = options.to_s.value_or(timeline.back().t);
  if (!(from >= timeline.front().t && to <= timeline.back().t && from < to)) {
    throw UsageError(fmt::format("--from/--to: [{}, {}] s must be an interval within the case's [{}, {}] s", from, to,
                                 timeline.front().t, timeline.back().t));
  }
  const auto started = std::chrono::steady_clock::now();
  report::PoseRenderer renderer(report::run_device(options.run), options.width, options.height, options.quality());
  report::VideoWriter video(options.video, options.width, options.height, options.fps);
  const double log_time_per_frame = options.speed / options.fps;
  const int frame_count = static_cast<int>((to - from) / log_time_per_frame) + 1;
  const report::View view = view_named(options.view);
  for (int frame = 0; frame < frame_count; ++frame) {
    const double t = from + frame * log_time_per_frame;
    const auto after = std::upper_bound(timeline.begin(), timeline.end(), t,
                                        [](double time, const report::TimedPose& p) { return time < p.t; });
    video.add_frame(renderer.Render(std::prev(after)->pose, view));
  }
  const int frames = video.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  out << fmt::format("Wrote {}: {} frames, {:.1f} s of the case at {}x speed, {} view ({:.1f} s to render)\n",
                     options.video, frames, to - from, options.speed, options.view, wall);
}

}  // namespace

void add_render_command(CLI::App& app, std::ostream& out) {
  auto options = std::make_shared<RenderOptions>();
  auto* render = app.add_subcommand(
      "render",
      "Render offscreen (OSMesa) to PNG, each muscle coloured by its pressure (blue 0, red max): a pose of "
      "a device (--out), the moments of a run (--run), or a video of a tracking run (--run --video, ffmpeg)");
  auto* placement = render->add_option("--placement", options->placement, "Placement file; default: the paper's device")
                        ->check(CLI::ExistingFile);
  auto* fe = render->add_option("--fe-deg", options->fe_deg, "Flexion (+) / extension (-) angle [deg]");
  auto* ur = render->add_option("--ur-deg", options->ur_deg, "Ulnar (+) / radial (-) deviation angle [deg]");
  auto* pressures =
      render->add_option("--pressures-kpa", options->pressures_kpa, "flexor,extensor,ulnar,radial pressures [kPa]");
  render
      ->add_option("--view", options->view,
                   "radial (flexion/extension) or palmar (ulnar/radial); a run's moments choose their own")
      ->check(CLI::IsMember({"radial", "palmar"}));
  auto* png = render->add_option("--out", options->out, "Output PNG of the pose");

  auto* run =
      render->add_option("--run", options->run, "A run directory (softwrist run --out)")->check(CLI::ExistingDirectory);
  auto* at = render->add_option("--at", options->at_s,
                                "Tracking runs: the instant nearest this time [s] instead of the "
                                "extremes");
  auto* case_index = render
                         ->add_option("--case", options->case_index,
                                      "Tracking runs: the case (controller, repetition); default: the log's first")
                         ->check(CLI::NonNegativeNumber);
  auto* out_dir = render->add_option("--out-dir", options->out_dir, "Where a run's PNGs go (default RUN_DIR/renders)");
  auto* video =
      render->add_option("--video", options->video, "Tracking runs: write a video of the case (e.g. run.mp4)");
  auto* fps = render->add_option("--fps", options->fps, "Video frames per second")->check(CLI::Range(1.0, 120.0));
  auto* speed = render->add_option("--speed", options->speed, "Video playback speed (2: twice real time)")
                    ->check(CLI::Range(0.05, 100.0));
  auto* from = render->add_option("--from", options->from_s, "Video start [s] (default: the case's start)");
  auto* to = render->add_option("--to", options->to_s, "Video end [s] (default: the case's end)");
  render->add_option("--width", options->width, "Image width [px]")->check(CLI::Range(16, 1280));
  render->add_option("--height", options->height, "Image height [px]")->check(CLI::Range(16, 960));
  render->add_flag(
      "--shadows", options->shadows,
      "Shadows and reflections, as in the viewer (off by default: they cost more than half the frame rate)");

  for (CLI::Option* pose_option : {placement, fe, ur, pressures, png}) pose_option->excludes(run);
  for (CLI::Option* run_option : {at, case_index, out_dir, video}) run_option->needs(run);
  for (CLI::Option* video_option : {fps, speed, from, to}) video_option->needs(video);
  at->excludes(video);
  out_dir->excludes(video);
  render->callback([options, &out] {
    if (options->run.empty()) {
      render_pose(*options, out);
    } else if (options->video.empty()) {
      render_moments(*options, out);
    } else {
      render_video(*options, out);
    }
  });
}

}  // namespace softwrist::cli
