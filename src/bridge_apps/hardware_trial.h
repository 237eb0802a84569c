#pragma once
// A tracking experiment on the real exosuit (or the device emulator) through the bridge: `softwrist trial
// experiments/<name>.json --device /dev/ttyACM0`. The same controllers, trajectory and loop (control::run_tracking)
// as the simulated experiment; the log is the same format (trial_log.h, source "hardware"), one row per loop
// iteration flushed as it is written, with the measured pressures and the device status beside the tracking
// columns. The true joint angles exist only in simulation, so they are absent.
//
// Each run (a controller and a repetition, numbered as the simulated experiment's cases) is its own session: the
// device starts vented, the muscles vent for `rest_s` while the subject holds the wrist at neutral, the loop zeroes the
// angles there (Sections Planar angle tracking and Spatial trajectory tracking), the loop runs, and the session ends
// with an emergency stop (vented). A controller command outside the regulator range stops the trial
// (TrackingOptions::OutOfRange::kStop). A fault (BridgeFault, ControllerFault or an interrupt) vents, ends the trial,
// and is recorded in bridge.json beside the log: nothing measured before it is lost, and the summary covers the runs
// that finished.

#include <atomic>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bridge/bridge_plant.h"
#include "experiments/experiment.h"

namespace softwrist::bridge {

struct TrialOptions {
  std::filesystem::path out;
  std::vector<std::string> controllers;          // by name; empty: every controller of the config
  std::optional<int> repetitions;                // default: the config's
  double rest_s = 1.0;                           // vented before each run [s]: the regulators empty
  bool overwrite = false;                        // a directory holding a trial log is refused unless set
  const std::atomic<bool>* interrupt = nullptr;  // set (by SIGINT) to stop, vented, after the current iteration
  std::ostream* progress = nullptr;
};

struct TrialResult {
  int runs_planned = 0;
  int runs_completed = 0;
  long rows_logged = 0;              // over all runs, those a fault ended included
  std::optional<std::string> fault;  // what ended the trial early
  nlohmann::json summary;            // of the completed runs, when there are any
};

// Runs the experiment `config` (a tracking experiment) on `plant`. Throws std::runtime_error for a config that is
// not a tracking experiment, an unknown controller or an occupied output directory, before anything moves.
TrialResult run_trial(const experiments::ExperimentConfig& config, BridgePlant& plant, const TrialOptions& options);

}  // namespace softwrist::bridge
