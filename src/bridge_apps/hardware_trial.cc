#include "bridge_apps/hardware_trial.h"

#include <fstream>
#include <memory>

#include <fmt/format.h>

#include "control/tracking_loop.h"
#include "experiments/runner.h"
#include "experiments/tracking.h"
#include "io/csv.h"

namespace softwrist::bridge {
namespace {

class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted") {}
};

std::vector<experiments::Column> hardware_columns() {
  std::vector<experiments::Column> columns = {{"case", "", "index of the case in the experiment"}};
  for (auto& c : experiments::tracking_columns()) columns.push_back(c);
  for (const char* muscle : control::kMuscleNames) {
    columns.push_back({fmt::format("p_{}_kpa", muscle), "kPa",
                       fmt::format("measured pressure, {} (the regulator's monitor output)", muscle)});
  }
  columns.push_back({"device_flags", "",
                     "device status bits: 1 vented, 2 emergency stop, 4 watchdog, 8 IMU fault, "
                     "16 limited, 32 no session (docs/bridge-protocol.md)"});
  return columns;
}

nlohmann::json stats_json(const BridgeStats& s) {
  return {{"commands_sent", s.commands_sent},           {"data_received", s.data_received},
          {"rejected_by_device", s.rejected_by_device}, {"garbled_from_device", s.garbled_from_device},
          {"out_of_sequence", s.out_of_sequence},       {"overlong_lines", s.overlong_lines},
          {"max_data_gap_s", s.max_data_gap_s}};
}

// bridge.json: the link, the device's limits, the counters and what happened to each run. Written after every
// run (through a temporary file, so a kill never leaves half of it).
void write_bridge_record(const std::filesystem::path& out, const BridgePlant& plant, const nlohmann::json& runs,
                         const std::optional<std::string>& fault) {
  const DeviceInfo& d = plant.device();
  const nlohmann::json record = {{"link", plant.link_name()},
                                 {"device",
                                  {{"protocol_version", d.version},
                                   {"max_kpa", d.limits.max_dkpa / 10.0},
                                   {"rate_kpa_s", d.limits.rate_dkpa_s / 10.0},
                                   {"timeout_ms", d.limits.timeout_ms}}},
                                 {"stats", stats_json(plant.stats())},
                                 {"runs", runs},
                                 {"fault", fault ? nlohmann::json(*fault) : nlohmann::json(nullptr)},
                                 {"last_device_flags", plant.device_flags()}};
  const std::filesystem::path tmp = out / "bridge.json.tmp";
  {
    std::ofstream file(tmp);
    file << record.dump(2) << '\n';
    if (!file) throw std::runtime_error(tmp.string() + ": cannot write");
  }
  std::filesystem::rename(tmp, out / "bridge.json");
}

const experiments::Tracking& tracking_experiment(const experiments::ExperimentConfig& config,
                                                 const experiments::Experiment& experiment) {
  const auto* tracking = dynamic_cast<const experiments::Tracking*>(&experiment);
  if (!tracking) {
    throw std::runtime_error(fmt::format("{}: a trial runs tracking experiments; this is a {} experiment",
                                         config.source, experiment.kind()));
  }
  return *tracking;
}

// The indices of the controllers named in `names`, in that order; all of them when `names` is empty.
std::vector<int> choose_controllers(const std::vector<std::unique_ptr<control::Controller>>& controllers,
                                    const std::vector<std::string>& names, const std::string& source) {
  std::vector<int> chosen;
  if (names.empty()) {
    for (std::size_t i = 0; i < controllers.size(); ++i) chosen.push_back(static_cast<int>(i));
  }
  for (const std::string& name : names) {
    std::vector<std::string> known;
    int found = -1;
    for (std::size_t i = 0; i < controllers.size(); ++i) {
      known.push_back(controllers[i]->name());
      if (controllers[i]->name() == name) found = static_cast<int>(i);
    }
    if (found < 0) {
      throw std::runtime_error(
          fmt::format("{}: no controller '{}' (it has: {})", source, name, fmt::join(known, ", ")));
    }
    chosen.push_back(found);
  }
  return chosen;
}

void check_trial_options(const TrialOptions& options, int repetitions) {
  if (repetitions < 1) throw std::runtime_error("a trial needs at least one repetition");
  const double rest_s = options.rest_s;
  if (!(rest_s >= 0.0)) throw std::runtime_error("the rest before each run must be >= 0 s");
  if (std::filesystem::exists(options.out / (std::string(experiments::kTrialLogName) + ".csv")) && !options.overwrite) {
    // A hardware trial is not resumed: the subject, the device and the session of the lost runs are gone.
    throw std::runtime_error(
        fmt::format("{} holds a trial log already (bridge.json says how its runs ended); a trial "
                    "is not resumed but run again: choose another --out, or replace it with "
                    "--overwrite",
                    options.out.string()));
  }
}

experiments::LogHeader trial_log_header(const experiments::ExperimentConfig& config,
                                        const experiments::Experiment& experiment, int case_count) {
  return {.kind = experiment.kind(),
          .source = "hardware",
          .config = config.json,
          .config_dir = config.base_dir.string(),
          .config_hash = experiments::content_hash(config.json.dump()),
          .model_hash = experiment.model_hash(),
          .columns = hardware_columns(),
          .case_count = case_count};
}

// What every run of a trial shares.
struct TrialContext {
  BridgePlant& plant;
  const experiments::Tracking& tracking;
  const control::TrackingOptions& loop;
  const TrialOptions& options;
  experiments::LogWriter& writer;
};

// One run (a session of one controller and repetition), its rows written as they come; a fault ends it vented and
// is kept in `result`. Either way the run is appended to `runs`.
void run_repetition(const TrialContext& trial, control::Controller& controller, int r, int case_index,
                    TrialResult& result, nlohmann::json& runs) {
  BridgePlant& plant = trial.plant;
  const TrialOptions& options = trial.options;
  long rows = 0;
  const auto write_sample = [&](const control::TrackingSample& s) {
    experiments::Row row = experiments::tracking_row(r, controller.name(), s);
    row.insert(row.begin(), std::to_string(case_index));
    for (double p : plant.measured_pressures_kpa()) row.push_back(io::format_number(p));
    row.push_back(std::to_string(plant.device_flags()));
    trial.writer.write_row(row);
    ++rows;
    if (options.interrupt && options.interrupt->load()) throw Interrupted();
  };
  try {
    plant.start_session();
    plant.wait_until(plant.time_s() + options.rest_s);
    control::run_tracking(plant, controller, trial.tracking.trajectory(), trial.loop, write_sample);
    plant.end_session();
    ++result.runs_completed;
    runs.push_back({{"case", case_index},
                    {"controller", controller.name()},
                    {"repetition", r},
                    {"rows", rows},
                    {"completed", true}});
  } catch (const std::exception& e) {
    // BridgeFault has vented already; the rest (a controller fault, an interrupt) vent here.
    try {
      if (plant.in_session()) plant.end_session();
    } catch (const BridgeFault&) {
    }
    result.fault =
        fmt::format("{} repetition {} (case {}), after {} rows: {}", controller.name(), r, case_index, rows, e.what());
    runs.push_back({{"case", case_index},
                    {"controller", controller.name()},
                    {"repetition", r},
                    {"rows", rows},
                    {"completed", false},
                    {"fault", e.what()}});
  }
  result.rows_logged += rows;
}

}  // namespace

TrialResult run_trial(const experiments::ExperimentConfig& config, BridgePlant& plant, const TrialOptions& options) {
  const std::unique_ptr<experiments::Experiment> experiment = experiments::make_experiment(config);
  const experiments::Tracking& tracking = tracking_experiment(config, *experiment);
  std::vector<std::unique_ptr<control::Controller>> controllers = tracking.make_controllers();
  const std::vector<int> chosen = choose_controllers(controllers, options.controllers, config.source);
  const int repetitions = options.repetitions.value_or(tracking.repetitions());
  check_trial_options(options, repetitions);

  experiments::LogHeader header =
      trial_log_header(config, *experiment, static_cast<int>(controllers.size()) * repetitions);
  std::filesystem::remove(options.out / "summary.json");
  experiments::LogWriter writer(options.out, experiments::kTrialLogName, header);
  control::TrackingOptions loop = tracking.options();
  loop.out_of_range = control::TrackingOptions::OutOfRange::kStop;
  const TrialContext trial{plant, tracking, loop, options, writer};

  TrialResult result{.runs_planned = static_cast<int>(chosen.size()) * repetitions};
  nlohmann::json runs = nlohmann::json::array();
  for (int c : chosen) {
    control::Controller& controller = *controllers[static_cast<std::size_t>(c)];
    for (int r = 0; r < repetitions && !result.fault; ++r) {
      const int case_index = c * repetitions + r;
      if (options.progress) {
        *options.progress << fmt::format("run {}/{}: {} repetition {} (case {})\n", result.runs_completed + 1,
                                         result.runs_planned, controller.name(), r, case_index);
      }
      run_repetition(trial, controller, r, case_index, result, runs);
      write_bridge_record(options.out, plant, runs, result.fault);
    }
    if (result.fault) break;
  }
  if (result.runs_completed > 0) {
    try {
      result.summary = experiments::summarize_run(*experiment, options.out, header);
    } catch (const std::exception& e) {
      result.summary = {{"error", e.what()}};
    }
  }
  return result;
}

}  // namespace softwrist::bridge
