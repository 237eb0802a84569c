#pragma once
// Runs an experiment's cases and writes its run directory:
//   trials.csv + trials.json   the trial log (trial_log.h), rows in case order, flushed as cases finish;
//   summary.json               the metrics, computed from the complete log (not written for a partial shard);
//   further files the summary names (curves for plots).
// Cases run on `jobs` threads; `shard K/N` runs only the cases i with i % N == K - 1, and merge_runs() joins the
// shards' directories into one run, so a cluster runs the shards as array jobs of its scheduler. A case's random
// stream depends only on the seed and its index, so threads and shards give the same numbers.

#include <filesystem>
#include <ostream>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/experiment.h"

namespace softwrist::experiments {

inline constexpr const char* kTrialLogName = "trials";

// What to do with a run directory that already holds a trial log.
enum class ExistingRun {
  kRefuse,     // an error that says what the directory holds and the commands that resume or re-run it
  kOverwrite,  // start again from the first case
  kResume,     // an interrupted run (killed, say): keep its complete cases and run the rest; the log ends as an
               // uninterrupted run's would (each case's random stream depends only on the seed and its index)
};

struct RunOptions {
  std::filesystem::path out;
  ExistingRun existing = ExistingRun::kRefuse;
  std::string command;  // how the user ran it ("softwrist run CONFIG --out DIR"), for the messages
  int jobs = 1;
  int shard_index = 1, shard_count = 1;
  std::ostream* progress = nullptr;  // progress bar (on a terminal) or progress lines; none when null
};

struct RunResult {
  int cases_run = 0;       // in this process
  int cases_resumed = 0;   // kept from the interrupted run
  bool complete = false;   // all cases of the experiment are in this directory's log
  nlohmann::json summary;  // when complete
};

RunResult run_experiment(const ExperimentConfig& config, const RunOptions& options);

// Joins the shard directories of one experiment (same config and model hash, every case exactly once) into `out`
// and writes its summary. Throws std::runtime_error naming the directory and the problem.
RunResult merge_runs(const std::vector<std::filesystem::path>& shard_dirs, const std::filesystem::path& out);

// The log's columns: "case", then the experiment's.
std::vector<Column> log_columns(const Experiment& experiment);
// Reads the run's complete log back, summarises it and writes summary.json (with the header's provenance).
nlohmann::json summarize_run(const Experiment& experiment, const std::filesystem::path& out, const LogHeader& header);

// Parses "K/N" (1 <= K <= N); throws std::invalid_argument otherwise.
std::pair<int, int> parse_shard(const std::string& text);

}  // namespace softwrist::experiments
