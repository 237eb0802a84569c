#pragma once
// `softwrist import`: a user's own measurements (a CSV with the units in its column names) turned into a trial log
// the diagnosis reads (docs/diagnosis.md lists the columns of each kind).

#include <filesystem>
#include <string>

#include "experiments/trial_log.h"
#include "io/csv.h"

namespace softwrist::diagnosis {

// What the user states of the measurement (docs/diagnosis.md, "Conventions"); each is written into the log's
// sidecar and read back by conventions_from_config, which checks it.
struct ImportOptions {
  std::string kind;             // torque-sweep, rom, tensile, trajectory
  bool hand_supported = false;  // a table carried the hand: posture hand_supported
  std::string posture;          // hand_supported, gravity_fe, gravity_ur; empty: the model's frame
  std::string torque_includes;  // torque sweeps: muscle, muscle+passive_wrist, ..., baseline_subtracted
  bool angles_zeroed = false;   // the angles read 0 at the trial's start
  double angle_resolution_deg = 0.0;
  std::string placement;          // the rig's placement file; empty: the model given to `diagnose`
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
