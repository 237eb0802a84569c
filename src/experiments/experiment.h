#pragma once
// An experiment: a list of independent cases (one wrist angle and pressure, one muscle, one optimizer start), each
// producing rows of the trial log, and a summary computed from the complete log. The runner (runner.h) runs the
// cases on threads or in shards and writes the log; the experiment never sees how.

#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/trial_log.h"
#include "io/csv.h"
#include "io/json_reader.h"

namespace softwrist::experiments {

inline constexpr const char* kConfigFormat = "softwrist.experiment/1";

using Row = std::vector<std::string>;

// An experiment config file (docs/experiments.md): its JSON and the directory its relative paths start from.
struct ExperimentConfig {
  nlohmann::json json;
  std::filesystem::path base_dir;
  std::string source;  // the file, for messages
  std::string name;    // the file's stem: runs/<name> by default
};

ExperimentConfig load_experiment_config(const std::filesystem::path& path);

class Experiment {
 public:
  virtual ~Experiment() = default;
  virtual std::string kind() const = 0;
  // The log's columns after the runner's leading "case" column.
  virtual std::vector<Column> columns() const = 0;
  virtual int case_count() const = 0;
  // Runs one case: its rows (cells matching columns()). Thread-safe; deterministic for a given seed and index.
  virtual std::vector<Row> run_case(int index) const = 0;
  // Identifies what the results depend on besides the config (the generated MJCF, reference data).
  virtual std::string model_hash() const = 0;
  // The experiment's metrics from its complete log ("case" column first); may write further files (curves for
  // plots) into run_dir.
  virtual nlohmann::json summarize(const io::CsvTable& log, const std::filesystem::path& run_dir) const = 0;
};

// The experiment a config describes; throws "<file>: <field>: <problem>" for a bad config.
std::unique_ptr<Experiment> make_experiment(const ExperimentConfig& config);

// The random stream of one case: the same for a given seed and case index, whatever the threads or shards.
std::mt19937_64 case_rng(std::uint64_t seed, int case_index);

// The repeated-trial fields most experiments share: "repetitions" (1..1000, default 3) and "seed" (default 1).
struct Repetitions {
  int count = 3;
  std::uint64_t seed = 1;
};
Repetitions read_repetitions(io::JsonReader& reader);

// A path field of a config, resolved against the config's directory.
std::filesystem::path config_path(io::JsonReader& reader, const std::string& key, const ExperimentConfig& config);

}  // namespace softwrist::experiments
