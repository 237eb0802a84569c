#pragma once
// `softwrist import`: a user's own measurements (a CSV with the units in its column names) turned into a trial log
// the diagnosis reads (docs/diagnosis.md lists the columns of each kind).

#include <filesystem>
#include <string>

#include "experiments/trial_log.h"
#include "io/csv.h"

namespace softwrist::diagnosis {

struct ImportOptions {
  std::string kind;               // torque-sweep, rom, tensile, trajectory
  bool hand_supported = false;    // trajectories and range of motion: a table carried the hand (no gravity)
  std::string muscle = "flexor";  // torque sweeps without a muscle column
  bool overwrite = false;
};

struct ImportResult {
  std::filesystem::path log;  // the written trials.csv
  std::size_t rows = 0;
};

// The log an import writes, in memory: every required column (with its unit) and every cell of `table` checked,
// and what the diagnosis reads from it. Throws std::runtime_error naming the file, line and column of the first
// problem.
experiments::TrialLog import_table(const io::CsvTable& table, const ImportOptions& options);

// Reads `csv`, checks every required column (with its unit) and every cell, and writes OUT/trials.csv and .json.
// Throws std::runtime_error naming the file, line and column of the first problem; writes nothing then.
ImportResult import_csv(const std::filesystem::path& csv, const std::filesystem::path& out,
                        const ImportOptions& options);

}  // namespace softwrist::diagnosis
