#include "diagnosis/csv_import.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "diagnosis/conventions.h"
#include "diagnosis/real_data.h"
#include "experiments/trial_log.h"
#include "io/csv.h"
#include "sim/device.h"

namespace softwrist::diagnosis {
namespace {

namespace fs = std::filesystem;

struct KindSpec {
  std::string log_kind;
  std::vector<std::string> required;
  std::vector<std::string> optional;
};

KindSpec kind_spec(const std::string& kind) {
  if (kind == "torque-sweep")
    return {"torque_sweep", {"angle_deg", "pressure_kpa", "torque_nm"}, {"repetition", "muscle"}};
  if (kind == "rom") return {"range_of_motion", {"muscle", "pressure_kpa", "limit_deg"}, {"repetition"}};
  if (kind == "tensile") return {"tensile", {"pressure_kpa", "contraction", "force_n"}, {"direction", "cycle"}};
  if (kind == "trajectory") {
    return {"trajectory",
            {"t_s", "cmd_flexor_kpa", "cmd_extensor_kpa", "cmd_ulnar_kpa", "cmd_radial_kpa", "angle_fe_deg",
             "angle_ur_deg"},
            {"case", "p_flexor_kpa", "p_extensor_kpa", "p_ulnar_kpa", "p_radial_kpa"}};
  }
  throw std::runtime_error(fmt::format("--kind: '{}' is not torque-sweep, rom, tensile or trajectory", kind));
}

// The column a required name maps to, or an error that says whether it is missing or lacks its unit.
int required_column(const io::CsvTable& table, const std::string& name) {
  if (const int c = table.find_column(name); c >= 0) return c;
  // Every required name but contraction (and muscle) ends in its unit: _deg, _kpa, _nm, _n, _s.
  const auto underscore = name.rfind('_');
  if (underscore != std::string::npos) {
    const std::string base = name.substr(0, underscore);
    for (const std::string& h : table.header()) {
      if (h == base) {
        throw std::runtime_error(fmt::format("{}: column '{}' states no unit; name it '{}' (units in the column names)",
                                             table.source(), h, name));
      }
      if (h.rfind(base + "_", 0) == 0 && h.find('_', base.size() + 1) == std::string::npos) {
        throw std::runtime_error(fmt::format("{}: column '{}': unit '{}' is not read; give '{}'", table.source(), h,
                                             h.substr(base.size() + 1), name));
      }
    }
  }
  return table.column(name);  // throws: missing column, with the columns there are
}

// The sidecar's config: the import's kind and muscle, and the conventions the user stated, checked as the diagnosis
// will read them (a relative placement from the working directory, where the user named it).
nlohmann::json import_config(const ImportOptions& options) {
  nlohmann::json config = {{"import_kind", options.kind}, {"muscle", options.muscle}};
  if (options.hand_supported) config["hand_supported"] = true;
  if (!options.posture.empty()) config["posture"] = options.posture;
  if (!options.torque_includes.empty()) {
    if (options.kind != "torque-sweep")
      throw std::runtime_error(fmt::format("--torque-includes: applies to torque-sweep, not {}", options.kind));
    config["torque_includes"] = options.torque_includes;
  }
  if (options.angles_zeroed) config["angles_zeroed_at_start"] = true;
  if (options.angle_resolution_deg != 0.0) config["angle_resolution_deg"] = options.angle_resolution_deg;
  if (!options.placement.empty()) {
    config["placement"] = fs::absolute(options.placement).lexically_normal().string();
    (void)sim::load_device(options.placement);  // a placement file that cannot be read fails the import, not later
  }
  (void)conventions_from_config(config, fs::current_path(), "import");
  return config;
}

}  // namespace

experiments::TrialLog import_table(const io::CsvTable& table, const ImportOptions& options) {
  const KindSpec spec = kind_spec(options.kind);
  if (table.row_count() == 0) throw std::runtime_error(fmt::format("{}: no rows", table.source()));
  std::vector<std::string> names;
  std::vector<int> source_columns;
  for (const std::string& name : spec.required) {
    names.push_back(name);
    source_columns.push_back(required_column(table, name));
  }
  for (const std::string& name : spec.optional) {
    if (const int c = table.find_column(name); c >= 0) {
      names.push_back(name);
      source_columns.push_back(c);
    }
  }
  for (const std::string& h : table.header()) {
    if (std::find(names.begin(), names.end(), h) == names.end()) {
      throw std::runtime_error(fmt::format("{}: column '{}' is not one {} reads (it reads {}, and optionally {})",
                                           table.source(), h, options.kind, fmt::join(spec.required, ", "),
                                           fmt::join(spec.optional, ", ")));
    }
  }
  if (!sim::muscle_from_name(options.muscle)) {
    throw std::runtime_error(fmt::format("--muscle: '{}' is not flexor, extensor, ulnar or radial", options.muscle));
  }
  // Numbers first, against the user's own lines (NaN, empty cells, text where a number belongs).
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == "muscle" || names[i] == "direction" || names[i] == "case") continue;  // labels
    for (std::size_t r = 0; r < table.row_count(); ++r) table.number(r, source_columns[i]);
  }
  // The log speaks the project's column names: a trajectory's angles are what the IMUs measured.
  std::vector<experiments::Column> columns;
  std::vector<std::string> log_names;
  for (const std::string& name : names) {
    std::string log_name = name == "angle_fe_deg"   ? "measured_fe_deg"
                           : name == "angle_ur_deg" ? "measured_ur_deg"
                                                    : name;
    const auto underscore = log_name.rfind('_');
    const std::string suffix = underscore == std::string::npos ? "" : log_name.substr(underscore + 1);
    const std::string unit = suffix == "deg"   ? "deg"
                             : suffix == "kpa" ? "kPa"
                             : suffix == "nm"  ? "N m"
                             : suffix == "n"   ? "N"
                             : suffix == "s"   ? "s"
                                               : "";
    columns.push_back({log_name, unit, "imported from " + name});
    log_names.push_back(log_name);
  }
  const nlohmann::json config = import_config(options);
  experiments::TrialLog log{
      .header = {.kind = spec.log_kind, .source = "import", .config = config, .columns = columns, .case_count = 1},
      .table = table.select(source_columns, log_names)};
  // What the diagnosis reads from the log is checked here, against the user's lines (times that do not increase,
  // pressures beyond the regulators, too few rows).
  (void)trials_from_log(log, "import");
  return log;
}

ImportResult import_csv(const fs::path& csv, const fs::path& out, const ImportOptions& options) {
  kind_spec(options.kind);  // an unknown kind before the file
  experiments::TrialLog log = import_table(io::CsvTable::Read(csv), options);
  if (fs::exists(out / "trials.csv") && !options.overwrite) {
    throw std::runtime_error(
        fmt::format("{}: already holds a log; choose another --out or give --overwrite", out.string()));
  }
  log.header.config["imported_from"] = fs::absolute(csv).string();
  // Written to a scratch directory and moved in place, so that a failed write leaves no half log behind.
  const fs::path scratch = out.string() + ".importing";
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  try {
    {
      experiments::LogWriter writer(scratch, "trials", log.header);
      for (std::size_t r = 0; r < log.table.row_count(); ++r) {
        std::vector<std::string> cells;
        for (std::size_t c = 0; c < log.table.header().size(); ++c)
          cells.push_back(log.table.cell(r, static_cast<int>(c)));
        writer.write_row(cells);
      }
    }
    fs::create_directories(out);
    for (const char* file : {"trials.csv", "trials.json"}) fs::rename(scratch / file, out / file);
    fs::remove_all(scratch);
  } catch (...) {
    fs::remove_all(scratch);
    throw;
  }
  return {out / "trials.csv", log.table.row_count()};
}

}  // namespace softwrist::diagnosis
