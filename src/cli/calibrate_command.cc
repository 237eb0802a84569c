#include "cli/calibrate_command.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "bridge_apps/device_emulator.h"
#include "bridge_apps/hardware_trial.h"
#include "calibration/calibration.h"
#include "cli/arguments.h"
#include "cli/bridge_commands.h"
#include "experiments/tracking.h"

namespace softwrist::cli {
namespace {

namespace fs = std::filesystem;

struct CalibrateOptions {
  BridgeCommandOptions bridge;
  std::string placement, out, routine = "experiments/calibration_routine.json";
  int jobs = 2;
  bool overwrite = false;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The routine's config with the nominal placement as its model.
experiments::ExperimentConfig routine_config(const std::string& routine, const std::string& placement) {
  experiments::ExperimentConfig config = experiments::load_experiment_config(routine);
  config.json["model"] = fs::absolute(placement).string();
  return config;
}

struct CalibrationRun {
  calibration::RoutineRecord routine;
  std::optional<calibration::Calibration> result;
  double wall_s = 0.0;
};

// The routine on the device, then the fit of what its log holds (unless nothing usable was logged).
CalibrationRun calibrate_on(bridge::BridgePlant& plant, const CalibrateOptions& o, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  CalibrationRun run;
  const fs::path dir(o.out);
  // What an earlier calibration left here is not this device's.
  for (const char* old : {"calibrated.json", "calibration.json"}) fs::remove(dir / old);
  run.routine = calibration::run_routine(routine_config(o.routine, o.placement), plant, dir / "routine", o.overwrite);
  if (run.routine.fault) err << "the routine stopped, vented: " << *run.routine.fault << "\n";
  // Less than 10 s (the first muscle's first two levels) is too little to fit.
  constexpr double kMinimumRun_s = 10.0;
  if (run.routine.run_s >= kMinimumRun_s) {
    run.result = calibration::calibrate_from_logs(dir / "routine", sim::load_device(o.placement), {.jobs = o.jobs});
  }
  run.wall_s = seconds_since(start);
  return run;
}

void print_calibration(const nlohmann::json& record, const fs::path& dir, std::ostream& out) {
  out << fmt::format("applied: {}\n", record["effects_applied"].empty()
                                          ? std::string("nothing (the data agree with the nominal)")
                                          : fmt::format("{}", fmt::join(record["effects_applied"], ", ")));
  for (const auto& p : record["parameters"]) {
    out << fmt::format("  {}.{} = {:.4g}  (95 % interval {:.4g} .. {:.4g})\n", p["effect"].get<std::string>(),
                       p["parameter"].get<std::string>(), p["value"].get<double>(), p["ci95"][0].get<double>(),
                       p["ci95"][1].get<double>());
  }
  out << "not identified:\n";
  for (const auto& u : record["not_identified"]) {
    out << fmt::format("  {}: {}\n", u["what"].get<std::string>(), u["why"].get<std::string>());
  }
  for (const auto& n : record["not_in_placement"])
    out << fmt::format("not in the placement file: {}\n", n.get<std::string>());
  out << fmt::format("{} ({:.1f} s), {}\n", (dir / "calibrated.json").string(), record["wall_s"].get<double>(),
                     (dir / "calibration.json").string());
}

void calibrate(const CalibrateOptions& o, std::ostream& out, std::ostream& err) {
  if (o.jobs < 1) throw UsageError("--jobs must be >= 1");
  std::optional<CalibrationRun> run;
  on_bridge(o.bridge, [&](bridge::BridgePlant& plant, const std::string& where) {
    err << fmt::format("calibration routine on {}\n", where);
    run = calibrate_on(plant, o, err);
  });
  const fs::path dir(o.out);
  if (!run->result) {
    fs::create_directories(dir);
    const nlohmann::json record = {
        {"calibrated", nullptr},
        {"routine", calibration::to_json(run->routine)},
        {"not_identified",
         nlohmann::json::array({{{"what", "everything"}, {"why", "too little of the routine ran to fit anything"}}})}};
    std::ofstream(dir / "calibration.json") << record.dump(2) << '\n';
    throw std::runtime_error(
        fmt::format("calibration: only {:.1f} s of the {:.0f} s routine ran ({}); nothing was "
                    "identified and no calibrated.json was written; {}",
                    run->routine.run_s, run->routine.planned_s, run->routine.fault.value_or("no fault recorded"),
                    (dir / "calibration.json").string()));
  }
  const nlohmann::json record = calibration::write_calibration(*run->result, run->routine, dir, run->wall_s);
  print_calibration(record, dir, out);
  if (run->routine.fault) {
    throw std::runtime_error(fmt::format(
        "calibration: the routine stopped after {:.1f} of {:.0f} s ({}); not run: {}; calibrated.json holds what the "
        "rest identified",
        run->routine.run_s, run->routine.planned_s, *run->routine.fault, fmt::join(run->routine.parts_not_run, ", ")));
  }
}

struct CalibrateBenchOptions {
  std::string emulator = "experiments/emulator/realistic.json";
  std::string placement = "models/rom_device.json";
  std::string planar = "experiments/planar_tracking.json", spatial = "experiments/spatial_tracking.json";
  std::string routine = "experiments/calibration_routine.json";
  std::string out = "out/bench_calibrate";
  std::string firmware;  // through the firmware in the loop
  int jobs = 2;
  bool json = false;
};

double mean_or_null(const nlohmann::json& a, const nlohmann::json& b) {
  if (!a.is_number() || !b.is_number()) return std::nan("");
  return 0.5 * (a.get<double>() + b.get<double>());
}

// One tracking task with the model-based controller on a fresh emulator of the same device; `model` is the
// controller's model. The task runs in the emulator's posture.
nlohmann::json track_with(const std::string& task_config, const fs::path& model, const CalibrateBenchOptions& o,
                          const fs::path& out) {
  experiments::ExperimentConfig config = experiments::load_experiment_config(task_config);
  const bridge::EmulatorConfig emulator_config = bridge::load_emulator_config(o.emulator);
  config.json["hand_supported"] = emulator_config.gravity == 0.0;
  config.json["model"] = fs::absolute(o.placement).string();
  config.json["controllers"] = nlohmann::json::array({{{"name", "model_based"}, {"model", fs::absolute(model)}}});
  config.json["repetitions"] = 1;
  nlohmann::json summary;
  on_bridge({.emulator = o.emulator, .firmware = o.firmware}, [&](bridge::BridgePlant& plant, const std::string&) {
    const bridge::TrialResult result = bridge::run_trial(config, plant, {.out = out, .overwrite = true});
    if (result.fault) throw std::runtime_error(fmt::format("{}: {}", task_config, *result.fault));
    summary = result.summary["controllers"][0];
  });
  return summary;
}

// The planar steps' and the spatial ellipse's figures with one controller model.
nlohmann::json tracking_figures(const fs::path& model, const CalibrateBenchOptions& o, const std::string& name) {
  const fs::path dir = fs::path(o.out) / "tracking";
  const nlohmann::json planar = track_with(o.planar, model, o, dir / (name + "_planar"));
  const nlohmann::json spatial = track_with(o.spatial, model, o, dir / (name + "_spatial"));
  return {{"model", model.string()},
          {"planar_steps",
           {{"rmse_fe_deg", planar["reachable_rmse_fe_deg"]},
            {"overshoot_pct",
             mean_or_null(planar["towards_extension"]["overshoot_pct"], planar["towards_flexion"]["overshoot_pct"])},
            {"rise_time_s",
             mean_or_null(planar["towards_extension"]["rise_time_s"], planar["towards_flexion"]["rise_time_s"])}}},
          {"spatial_ellipse",
           {{"rmse_fe_deg", spatial["reachable_rmse_fe_deg"]}, {"rmse_ur_deg", spatial["reachable_rmse_ur_deg"]}}}};
}

// calibrated / true - 1 of each figure (how far the calibrated model's tracking is from the true model's).
nlohmann::json relative_to_true(const nlohmann::json& calibrated, const nlohmann::json& truth) {
  nlohmann::json out;
  for (const char* task : {"planar_steps", "spatial_ellipse"}) {
    for (const auto& [key, value] : truth[task].items()) {
      const nlohmann::json& c = calibrated[task][key];
      if (value.is_number() && c.is_number() && value.get<double>() != 0.0) {
        out[task][key] = c.get<double>() / value.get<double>() - 1.0;
      }
    }
  }
  return out;
}

void bench_calibrate(const CalibrateBenchOptions& o, std::ostream& out, std::ostream& err) {
  if (o.jobs < 1) throw UsageError("--jobs must be >= 1");
  const fs::path dir(o.out);
  fs::create_directories(dir);
  // The emulated device's own placement (its effects that a placement holds): the "true" model.
  const fs::path truth = dir / "true_model.json";
  std::ofstream(truth) << sim::device_to_json(bridge::emulated_description(bridge::load_emulator_config(o.emulator)));

  const CalibrateOptions c{.bridge = {.emulator = o.emulator, .firmware = o.firmware},
                           .placement = o.placement,
                           .out = (dir / "calibration").string(),
                           .routine = o.routine,
                           .jobs = o.jobs,
                           .overwrite = true};
  std::optional<CalibrationRun> run;
  on_bridge(c.bridge, [&](bridge::BridgePlant& plant, const std::string&) { run = calibrate_on(plant, c, err); });
  if (!run->result) throw std::runtime_error("bench calibrate: the routine did not run");
  const nlohmann::json record = calibration::write_calibration(*run->result, run->routine, c.out, run->wall_s);

  nlohmann::json models;
  models["nominal"] = tracking_figures(o.placement, o, "nominal");
  models["calibrated"] = tracking_figures(fs::path(c.out) / "calibrated.json", o, "calibrated");
  models["true"] = tracking_figures(truth, o, "true");
  const nlohmann::json result = {
      {"emulator", o.emulator},
      {"firmware", o.firmware.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.firmware)},
      {"routine_s", run->routine.planned_s},
      {"calibration_wall_s", run->wall_s},
      {"parameters", record["parameters"]},
      {"models", models},
      {"calibrated_relative_to_true", relative_to_true(models["calibrated"], models["true"])},
      {"nominal_relative_to_true", relative_to_true(models["nominal"], models["true"])}};
  std::ofstream(dir / "bench_calibrate.json") << result.dump(2) << '\n';
  if (o.json) {
    out << result.dump(2) << '\n';
    return;
  }
  out << fmt::format("routine {:.0f} s, calibration {:.1f} s wall\n", run->routine.planned_s, run->wall_s);
  out << "model        steps: rmse_fe_deg  overshoot_pct  rise_time_s   ellipse: rmse_fe_deg  rmse_ur_deg\n";
  for (const char* name : {"nominal", "calibrated", "true"}) {
    const nlohmann::json& m = models[name];
    const auto num = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : std::nan(""); };
    out << fmt::format("{:<12} {:>18.3f} {:>14.1f} {:>12.3f} {:>20.3f} {:>12.3f}\n", name,
                       num(m["planar_steps"]["rmse_fe_deg"]), num(m["planar_steps"]["overshoot_pct"]),
                       num(m["planar_steps"]["rise_time_s"]), num(m["spatial_ellipse"]["rmse_fe_deg"]),
                       num(m["spatial_ellipse"]["rmse_ur_deg"]));
  }
  out << (dir / "bench_calibrate.json").string() << "\n";
}

}  // namespace

void add_calibrate_command(CLI::App& app, std::ostream& out, std::ostream& err) {
  auto o = std::make_shared<CalibrateOptions>();
  auto* command = app.add_subcommand(
      "calibrate",
      "Calibrate the exosuit from its own sensors: a short open-loop routine through the bridge, the fit of the "
      "effects it identifies, and the calibrated placement file for the model-based controller "
      "(docs/calibration.md)");
  add_bridge_options(*command, o->bridge);
  command->add_option("--placement", o->placement, "The nominal placement file of the device")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--out", o->out, "Output directory: routine/ (the log), calibrated.json, calibration.json")
      ->required();
  command->add_option("--routine", o->routine, "The routine (a tracking config whose controller is excitation)")
      ->check(CLI::ExistingFile);
  command->add_option("--jobs", o->jobs, "Threads of the fit");
  command->add_flag("--overwrite", o->overwrite, "Replace a routine log already in the directory");
  command->callback([o, &out, &err] { calibrate(*o, out, err); });
}

void add_calibrate_bench(CLI::App& bench, std::ostream& out, std::ostream& err) {
  auto o = std::make_shared<CalibrateBenchOptions>();
  auto* command = bench.add_subcommand(
      "calibrate",
      "Calibrate the emulator's realistic device, then track the planar steps and the spatial ellipse with the "
      "model-based controller given the nominal, the calibrated and the device's true model");
  command->add_option("--emulator", o->emulator, "Emulator config of the device")->check(CLI::ExistingFile);
  command->add_option("--placement", o->placement, "Its nominal placement file")->check(CLI::ExistingFile);
  command->add_option("--out", o->out, "Where the runs go");
  command->add_option("--jobs", o->jobs, "Threads of the fit");
  command
      ->add_option("--firmware", o->firmware,
                   "Run the routine and the tracking through this firmware on a simulated ATmega328P (docs/hil.md)")
      ->check(CLI::ExistingFile);
  command->add_flag("--json", o->json, "Print the figures as JSON");
  command->callback([o, &out, &err] { bench_calibrate(*o, out, err); });
}

}  // namespace softwrist::cli
