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
  run.routine = calibration::run_routine(routine_config(o.routine, o.placement), plant, dir / "routine", o.overwrite);
  if (run.routine.fault) err << "the routine stopped, vented: " << *run.routine.fault << "\n";
  // A fit needs the first muscle's steps at least.
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
    const nlohmann::json record = {{"routine",
                                    {{"planned_s", run->routine.planned_s},
                                     {"run_s", run->routine.run_s},
                                     {"fault", run->routine.fault.value_or("")},
                                     {"parts_not_run", run->routine.parts_not_run}}},
                                   {"not_identified", "everything: too little of the routine ran to fit anything"}};
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

}  // namespace softwrist::cli
