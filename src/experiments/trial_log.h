#pragma once
// The trial log: the one format every experiment, hardware trial and import writes, and the reports and the gap
// diagnosis read (docs/log-format.md). A log is two files side by side:
//   <name>.csv   the data, one row per measurement, units in the column names (angle_deg, torque_nm, ...),
//                flushed row by row so that an interrupted run keeps every row it wrote;
//   <name>.json  the sidecar: format, kind, source, software version, the config as run, its hash, the model's
//                hash, the columns with units and descriptions, and which cases (shard) the rows cover.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/csv.h"

namespace softwrist::experiments {

inline constexpr const char* kLogFormat = "softwrist.log/1";

struct Column {
  std::string name;  // with the unit as suffix where it has one: angle_deg, torque_nm, pressure_kpa
  std::string unit;  // "deg", "N m", "kPa", "cm", "" for counts and labels
  std::string description;
};

struct LogHeader {
  std::string kind;                   // torque_validation, range_of_motion, design_optimization, ...
  std::string source = "simulation";  // simulation, hardware, import
  nlohmann::json config;              // the experiment config as run
  std::string config_dir;             // the directory its relative paths start from
  std::string config_hash;
  std::string model_hash;  // of what determines the simulated device (generated MJCF, reference data)
  std::vector<Column> columns;
  int case_count = 0;  // cases of the whole experiment
  int shard_index = 1, shard_count = 1;
};

nlohmann::json to_json(const LogHeader& header);
// Throws std::runtime_error("<source>: <field>: <problem>") for a sidecar of another format or with missing fields.
LogHeader log_header_from_json(const nlohmann::json& sidecar, const std::string& source);

// Writes <dir>/<name>.json at once and <dir>/<name>.csv row by row.
class LogWriter {
 public:
  LogWriter(const std::filesystem::path& dir, const std::string& name, const LogHeader& header);
  // Resumes a log: <dir>/<name>.csv is replaced, atomically, by the header and `kept_rows` (the complete cases of
  // an interrupted run), and rows are appended after them.
  LogWriter(const std::filesystem::path& dir, const std::string& name, const LogHeader& header,
            const std::vector<std::vector<std::string>>& kept_rows);
  void write_row(const std::vector<std::string>& cells) { csv_.write_row(cells); }
  const std::filesystem::path& csv_path() const { return csv_.path(); }

 private:
  io::CsvWriter csv_;
};

struct TrialLog {
  LogHeader header;
  io::CsvTable table;
  // The line of a last row cut short by a killed writer (no newline after it), which is left out; 0 when none.
  // Every row before it is whole: the writer flushes row by row.
  int unfinished_line = 0;
};

// Reads <dir>/<name>.json and .csv and checks that the CSV's header is the sidecar's column list.
TrialLog read_log(const std::filesystem::path& dir, const std::string& name);

// A stable content hash for provenance: "fnv1a64:<16 hex digits>" (FNV-1a, 64 bit; not cryptographic).
std::string content_hash(std::string_view text);

}  // namespace softwrist::experiments
