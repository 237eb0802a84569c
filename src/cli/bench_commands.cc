#include "cli/bench_commands.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/arguments.h"
#include "cli/bridge_commands.h"
#include "cli/calibrate_command.h"
#include "cli/diagnose_commands.h"
#include "experiments/design_optimization.h"
#include "experiments/experiment.h"
#include "experiments/tracking.h"
#include "physics/units.h"
#include "report/offscreen_renderer.h"
#include "sim/device.h"
#include "sim/model.h"
#include "sim/model_builder.h"

namespace softwrist::cli {
namespace {

// 15 rounds of 50 000 steps (3 s): with 7 of 20 000 the ratio spread 1.078-1.104 over five runs on an idle machine,
// with these 1.081-1.088 over four.
struct SimBenchOptions {
  int steps = 50000;
  int rounds = 15;
  bool json = false;
};

// The muscles' commands at step i: a slow square wave, so that the wrist moves through straight and wrapped
// configurations.
void drive(int i, mjData* d) {
  const bool phase = (i / 1000) % 2 == 0;
  d->ctrl[0] = phase ? 120.0 : 15.0;
  d->ctrl[1] = phase ? 15.0 : 120.0;
  d->ctrl[2] = phase ? 80.0 : 20.0;
  d->ctrl[3] = phase ? 20.0 : 80.0;
}

// One run from reset: the plugin model driven by the square wave, recording each step's actuator forces; or the
// replay model given those forces as its controls. Returns steps per second; `qpos` gets the trajectory.
struct SimRun {
  const sim::Model& model;
  mjData* data;
  std::vector<double>* forces;  // steps x nu: written by the plugin run, read by the replay
  bool replay;
};
double steps_per_second(const SimRun& run, int steps, std::vector<double>& qpos) {
  const mjModel* m = run.model.get();
  mjData* d = run.data;
  mj_resetData(m, d);
  qpos.resize(static_cast<std::size_t>(steps) * 2);
  const auto nu = static_cast<std::size_t>(m->nu);
  run.forces->resize(static_cast<std::size_t>(steps) * nu);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) {
    const auto step = static_cast<std::size_t>(i);
    if (run.replay) {
      std::copy_n(run.forces->begin() + static_cast<std::ptrdiff_t>(step * nu), nu, d->ctrl);
    } else {
      drive(i, d);
    }
    mj_step(m, d);
    if (!run.replay) std::copy_n(d->actuator_force, nu, run.forces->begin() + static_cast<std::ptrdiff_t>(step * nu));
    qpos[2 * step] = d->qpos[0];
    qpos[2 * step + 1] = d->qpos[1];
  }
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  return steps / elapsed.count();
}

// The plugin's cost alone: the fPAM model driven by commands, against MuJoCo's own <general> actuators on the same
// tendons replaying the forces the plugin produced (force = ctrl), so that both runs move identically and differ
// only in who computes the force. Interleaved rounds, best of each, under the same machine load.
int run_sim_bench(const SimBenchOptions& options, std::ostream& out) {
  if (options.steps < 100 || options.rounds < 1) throw UsageError("--steps must be >= 100 and --rounds >= 1");
  const sim::DeviceDescription device = sim::paper_device();
  const auto plugins = sim::PluginSet::Default();
  const sim::Model plugin = sim::Model::FromXml(sim::build_model_xml(device), plugins, "plugin model");
  const sim::Model replay = sim::Model::FromXml(
      sim::build_model_xml(device, {.actuators = sim::ActuatorKind::kForceReplay}), plugins, "replay model");
  const sim::Data plugin_data = sim::make_data(plugin), replay_data = sim::make_data(replay);
  std::vector<double> forces, plugin_qpos, replay_qpos;
  double best_plugin = 0.0, best_replay = 0.0, max_difference = 0.0;
  for (int round = 0; round < options.rounds; ++round) {
    best_plugin = std::max(best_plugin,
                           steps_per_second({plugin, plugin_data.get(), &forces, false}, options.steps, plugin_qpos));
    best_replay =
        std::max(best_replay, steps_per_second({replay, replay_data.get(), &forces, true}, options.steps, replay_qpos));
    for (std::size_t i = 0; i < plugin_qpos.size(); ++i)
      max_difference = std::max(max_difference, std::abs(plugin_qpos[i] - replay_qpos[i]));
  }
  const double ratio = best_replay / best_plugin;  // the plugin's step cost over the same step without it
  const bool same_motion = max_difference <= 1e-9;
  if (options.json) {
    out << nlohmann::json{{"plugin_steps_per_s", best_plugin},
                          {"builtin_steps_per_s", best_replay},
                          {"ratio", ratio},
                          {"max_joint_difference_rad", max_difference},
                          {"same_motion", same_motion},
                          {"steps", options.steps},
                          {"rounds", options.rounds},
                          {"stretch", physics::to_string(device.stretch_mode)}}
               .dump()
        << '\n';
  } else {
    out << fmt::format("4-muscle wrist model, {} steps x {} rounds (best), stretch {}\n", options.steps, options.rounds,
                       physics::to_string(device.stretch_mode))
        << fmt::format("  fPAM plugin                            {:>10.0f} steps/s\n", best_plugin)
        << fmt::format("  built-in <general> replaying its forces {:>9.0f} steps/s\n", best_replay)
        << fmt::format("  joint trajectories differ by at most {:.2g} rad ({})\n", max_difference,
                       same_motion ? "the same motion" : "NOT the same motion: the ratio is not the plugin's cost")
        << fmt::format("  ratio (plugin step cost / built-in step cost) {:.3f}  (target <= 1.10)\n", ratio);
  }
  return same_motion ? 0 : 1;
}

struct OptimizeBenchOptions {
  std::string config = "experiments/design_optimization.json";
  int jobs = 2;
  double exhaustive_resolution_cm = 0.25;
  bool json = false;
};

nlohmann::json placement_cm(const physics::Placement& p) {
  return {units::m_to_cm(p.d1), units::m_to_cm(p.w1), units::m_to_cm(p.d2), units::m_to_cm(p.w2)};
}

// The full multi-start of Section Parameter optimization, timed, beside the exhaustive grid search that checks it.
int run_optimize_bench(const OptimizeBenchOptions& options, std::ostream& out) {
  if (options.jobs < 1) throw UsageError("--jobs must be >= 1");
  if (!(options.exhaustive_resolution_cm > 0.0)) throw UsageError("--exhaustive-resolution-cm must be > 0");
  const auto config = experiments::load_experiment_config(options.config);
  io::JsonReader reader(config.json, config.source, "");
  (void)reader.text("format"), (void)reader.text("kind"), (void)reader.text("description", "");
  experiments::DesignSettings settings = experiments::read_design_settings(reader, config);
  settings.options.jobs = options.jobs;
  const auto seconds_since = [](auto start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  auto start = std::chrono::steady_clock::now();
  const optimize::DesignResult result = optimize::optimize_design(settings.problem, settings.options);
  const double wall = seconds_since(start);
  const double r = units::cm_to_m(options.exhaustive_resolution_cm);
  start = std::chrono::steady_clock::now();
  const optimize::LocalSolution check =
      optimize::exhaustive_search(settings.problem, {.d1 = r, .w1 = r, .d2 = r, .w2 = r}, options.jobs);
  const double exhaustive_wall = seconds_since(start);
  const bool not_worse = result.best.objective <= check.objective + 1e-9;
  const auto& b = result.best.placement;
  const auto& c = check.placement;
  const double distance_cm = units::m_to_cm(
      std::max({std::abs(b.d1 - c.d1), std::abs(b.w1 - c.w1), std::abs(b.d2 - c.d2), std::abs(b.w2 - c.w2)}));
  constexpr double kPaperWallS = 24 * 60;  // Section Parameter optimization: "24 minutes on average"
  const bool same_optimum = not_worse && distance_cm <= options.exhaustive_resolution_cm;
  const double evaluations_per_s = (result.evaluations + check.evaluations) / (wall + exhaustive_wall);
  if (options.json) {
    out << nlohmann::json{{"wall_s", wall},
                          {"evaluations", result.evaluations},
                          {"starts", result.starts},
                          {"placement_cm", placement_cm(b)},
                          {"objective", result.best.objective},
                          {"jobs", options.jobs},
                          {"algorithm", settings.options.algorithm},
                          {"exhaustive_wall_s", exhaustive_wall},
                          {"exhaustive_points", check.evaluations},
                          {"exhaustive_placement_cm", placement_cm(c)},
                          {"exhaustive_objective", check.objective},
                          {"same_optimum", same_optimum},
                          // The exhaustive grid is the guarantee: the global optimum on it, every point evaluated.
                          {"global_optimum_wall_s", exhaustive_wall},
                          {"objective_evaluations_per_s", evaluations_per_s},
                          {"paper_wall_s", kPaperWallS}}
               .dump()
        << '\n';
  } else {
    out << fmt::format("design optimization ({}), {} starts on {} threads, {}\n", options.config, result.starts,
                       options.jobs, settings.options.algorithm)
        << fmt::format(
               "  multi-start   {:>8.2f} s  {:>9} evaluations  optimum d1 {:.2f} w1 {:.2f} d2 {:.2f} w2 {:.2f} cm"
               "  objective {:.4f} N m\n",
               wall, result.evaluations, units::m_to_cm(b.d1), units::m_to_cm(b.w1), units::m_to_cm(b.d2),
               units::m_to_cm(b.w2), result.best.objective)
        << fmt::format(
               "  exhaustive    {:>8.2f} s  {:>9} points       optimum d1 {:.2f} w1 {:.2f} d2 {:.2f} w2 {:.2f} cm"
               "  objective {:.4f} N m ({} cm grid)\n",
               exhaustive_wall, check.evaluations, units::m_to_cm(c.d1), units::m_to_cm(c.w1), units::m_to_cm(c.d2),
               units::m_to_cm(c.w2), check.objective, options.exhaustive_resolution_cm)
        << fmt::format("  same optimum: {} (multi-start not worse, within one grid step)\n",
                       same_optimum ? "yes" : "NO")
        << fmt::format("  objective evaluations {:.3g}/s; the global optimum on the grid in {:.2f} s\n",
                       evaluations_per_s, exhaustive_wall)
        << fmt::format("  paper (MATLAB fminsearch): 24 min in all; target here < 10 s; ratio paper/here {:.0f}\n",
                       kPaperWallS / wall);
  }
  return 0;
}

struct ControlBenchOptions {
  std::string config = "experiments/spatial_tracking.json";
  bool json = false;
};

// Real-time factor (simulated seconds per wall second) of each controller with the simulated plant along a
// tracking config's trajectory, beside the plant alone driven with fixed pressures at the same loop rate.
int run_control_bench(const ControlBenchOptions& options, std::ostream& out) {
  const auto experiment = experiments::make_experiment(experiments::load_experiment_config(options.config));
  const auto* tracking = dynamic_cast<const experiments::Tracking*>(experiment.get());
  if (tracking == nullptr) throw UsageError(options.config + " is not a tracking experiment config");
  const double duration = tracking->trajectory().duration_s();
  const auto wall_since = [](auto start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  nlohmann::json rows = nlohmann::json::array();
  double plant_only_rtf = 0.0;
  for (const auto& controller : tracking->make_controllers()) {
    sim::SimulatedPlant plant = tracking->make_plant(1);
    auto start = std::chrono::steady_clock::now();
    control::run_tracking(plant, *controller, tracking->trajectory(), tracking->options(), nullptr);
    const double with_controller = wall_since(start);
    sim::SimulatedPlant bare = tracking->make_plant(1);
    start = std::chrono::steady_clock::now();
    for (double t = 0.0; t < duration; t += controller->period_s()) {
      (void)bare.read_angles();
      bare.command_pressures_kpa({20.0, 20.0, 20.0, 20.0});
      bare.wait_until(t + controller->period_s());
    }
    const double plant_alone = wall_since(start);
    plant_only_rtf = std::max(plant_only_rtf, duration / plant_alone);
    rows.push_back({{"controller", controller->name()},
                    {"simulated_s", duration},
                    {"wall_s", with_controller},
                    {"real_time_factor", duration / with_controller},
                    {"plant_alone_wall_s", plant_alone},
                    {"cost_ratio", with_controller / plant_alone}});
  }
  if (options.json) {
    out << nlohmann::json{{"config", options.config}, {"controllers", rows}}.dump() << '\n';
    return 0;
  }
  out << fmt::format("controller + simulated plant along {} ({:.0f} s simulated)\n", options.config, duration);
  for (const auto& r : rows) {
    out << fmt::format("  {:<12} {:>7.2f} s wall  real-time factor {:>6.1f}  (plant alone {:.2f} s; ratio {:.2f})\n",
                       r["controller"].get<std::string>(), r["wall_s"].get<double>(),
                       r["real_time_factor"].get<double>(), r["plant_alone_wall_s"].get<double>(),
                       r["cost_ratio"].get<double>());
  }
  out << "  real time needs a factor >= 1; the ratio is the loop's cost over the plant's alone\n";
  return 0;
}

struct RenderBenchOptions {
  int frames = 60;
  bool json = false;
};

// A renderer's steady frame rate, and what its construction and first frame cost: llvmpipe compiles its shaders on
// first use (about 0.2 s here, a quarter of 60 frames' time), once per renderer, so a report or a video pays it once.
struct FrameRate {
  double frames_per_s = 0, first_frame_s = 0;
};

// Offscreen frames per second of the paper's device (OSMesa, software rendering, read back), the wrist sweeping
// through flexion so that every frame differs: the reports' and videos' quality at 640x480 and, for scale, 320x240,
// and the viewer's look (shadows, reflections, the model's tessellation) at 640x480, in the same run. Each size is
// timed after one untimed frame (at 640x480, the renderer's construction and that frame are reported apart).
int run_render_bench(const RenderBenchOptions& options, std::ostream& out) {
  if (options.frames < 1) throw UsageError("--frames must be >= 1");
  const sim::DeviceDescription device = sim::paper_device();
  const auto plugins = sim::PluginSet::Default();
  const sim::Model model = sim::Model::FromXml(sim::build_model_xml(device), plugins, "paper device");
  const sim::Data data = sim::make_data(model);
  const int fe = model->jnt_qposadr[model.id(mjOBJ_JOINT, "wrist_fe")];
  const double max_kpa = units::pa_to_kpa(device.regulator.max_pressure);
  const auto frames_per_second = [&](int width, int height, const report::RenderQuality& quality) {
    const auto start = std::chrono::steady_clock::now();
    report::OffscreenRenderer renderer(model, width, height, quality);
    const auto render = [&](int i) {
      data->qpos[fe] = units::deg_to_rad(-60.0 + 120.0 * i / options.frames);
      data->act[0] = max_kpa * i / options.frames;
      mj_forward(model.get(), data.get());
      (void)renderer.Render(data.get(), report::View::kRadial, max_kpa);
    };
    render(options.frames);
    const auto warm = std::chrono::steady_clock::now();
    for (int i = 0; i < options.frames; ++i) render(i);
    const auto end = std::chrono::steady_clock::now();
    return FrameRate{options.frames / std::chrono::duration<double>(end - warm).count(),
                     std::chrono::duration<double>(warm - start).count()};
  };
  const report::RenderQuality viewer_look{.shadows = true, .reflections = true, .slices = model->vis.quality.numslices};
  const FrameRate full = frames_per_second(640, 480, {}), quarter = frames_per_second(320, 240, {});
  const FrameRate looked = frames_per_second(640, 480, viewer_look);
  if (options.json) {
    out << nlohmann::json{{"fps_640x480", full.frames_per_s},
                          {"fps_320x240", quarter.frames_per_s},
                          {"fps_640x480_viewer_look", looked.frames_per_s},
                          {"first_frame_s_640x480", full.first_frame_s},
                          {"frames", options.frames}}
               .dump()
        << '\n';
  } else {
    out << fmt::format("offscreen rendering (OSMesa) of the paper's device, {} frames each after a first\n",
                       options.frames)
        << fmt::format("  640x480 {:>7.1f} frames/s (the renderer and its first frame {:.3f} s)\n", full.frames_per_s,
                       full.first_frame_s)
        << fmt::format("  320x240 {:>7.1f} frames/s (ratio {:.2f})\n", quarter.frames_per_s,
                       quarter.frames_per_s / full.frames_per_s)
        << fmt::format(
               "  640x480 with shadows, reflections and {} slices (the viewer's look) {:>7.1f} frames/s "
               "(ratio {:.2f})\n",
               viewer_look.slices, looked.frames_per_s, full.frames_per_s / looked.frames_per_s);
  }
  return 0;
}

}  // namespace

void add_bench_commands(CLI::App& app, std::ostream& out, std::ostream& err) {
  auto* bench = app.add_subcommand("bench", "Speed figures, compared side by side in one run");
  bench->require_subcommand(1);
  auto options = std::make_shared<SimBenchOptions>();
  auto* sim_bench = bench->add_subcommand("sim",
                                          "Steps per second of the model with the fPAM plugin and with "
                                          "MuJoCo's built-in <general> tendon actuators replaying the plugin's "
                                          "forces (the same motion), and their ratio");
  sim_bench->add_option("--steps", options->steps, "Steps per round");
  sim_bench->add_option("--rounds", options->rounds, "Interleaved rounds; the best of each is reported");
  sim_bench->add_flag(
      "--json", options->json,
      "Print {plugin_steps_per_s, builtin_steps_per_s, ratio, max_joint_difference_rad, same_motion, ...}");
  sim_bench->callback([options, &out] { run_sim_bench(*options, out); });

  auto optimize_options = std::make_shared<OptimizeBenchOptions>();
  auto* optimize_bench = bench->add_subcommand(
      "optimize", "Wall time of the full multi-start design optimization, beside the exhaustive grid check");
  optimize_bench->add_option("--config", optimize_options->config, "A design_optimization experiment config")
      ->check(CLI::ExistingFile);
  optimize_bench->add_option("--jobs", optimize_options->jobs, "Threads");
  optimize_bench->add_option("--exhaustive-resolution-cm", optimize_options->exhaustive_resolution_cm,
                             "Grid step of the exhaustive check [cm]");
  optimize_bench->add_flag("--json", optimize_options->json,
                           "Print {wall_s, evaluations, placement_cm, objective, exhaustive_*, same_optimum, ...}");
  optimize_bench->callback([optimize_options, &out] { run_optimize_bench(*optimize_options, out); });

  auto control_options = std::make_shared<ControlBenchOptions>();
  auto* control_bench = bench->add_subcommand(
      "control", "Real-time factor of each controller with the simulated plant, beside the plant alone");
  control_bench->add_option("--config", control_options->config, "A tracking experiment config")
      ->check(CLI::ExistingFile);
  control_bench->add_flag("--json", control_options->json,
                          "Print {config, controllers: [{controller, real_time_factor, wall_s, cost_ratio, ...}]}");
  control_bench->callback([control_options, &out] { run_control_bench(*control_options, out); });

  auto render_options = std::make_shared<RenderBenchOptions>();
  auto* render_bench = bench->add_subcommand("render", "Offscreen frames per second (OSMesa) at 640x480 and 320x240");
  render_bench->add_option("--frames", render_options->frames, "Frames per size");
  render_bench->add_flag("--json", render_options->json,
                         "Print {fps_640x480, fps_320x240, fps_640x480_viewer_look, first_frame_s_640x480, frames}");
  render_bench->callback([render_options, &out] { run_render_bench(*render_options, out); });
  add_bridge_bench(*bench, out);
  add_hil_bench(*bench, out);
  add_diagnose_bench(*bench, out);
  add_calibrate_bench(*bench, out, err);
}

}  // namespace softwrist::cli
