#include "diagnosis/real_data.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "experiments/trial_log.h"
#include "io/text_file.h"
#include "physics/units.h"

namespace softwrist::diagnosis {
namespace fs = std::filesystem;
using units::deg_to_rad;
using units::kpa_to_pa;

const char* to_string(TrialKind kind) {
  switch (kind) {
    case TrialKind::kTorqueSweep:
      return "torque_sweep";
    case TrialKind::kRangeOfMotion:
      return "range_of_motion";
    case TrialKind::kTensile:
      return "tensile";
    case TrialKind::kTrajectory:
      return "trajectory";
  }
  return "?";
}

// Cluster index of each value: sorted, a new cluster where the gap exceeds `gap`.
std::vector<int> clusters(const std::vector<double>& values, double gap) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<int> id(values.size(), 0);
  int current = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (k > 0 && values[order[k]] - values[order[k - 1]] > gap) ++current;
    id[order[k]] = current;
  }
  return id;
}

std::vector<int> set_angle_clusters(const std::vector<double>& angles_deg) {
  const std::vector<int> cluster = clusters(angles_deg, kHeldAngleGapDeg);
  const int count = cluster.empty() ? 0 : *std::max_element(cluster.begin(), cluster.end()) + 1;
  std::vector<double> sum(static_cast<std::size_t>(count), 0.0);
  std::vector<int> size(static_cast<std::size_t>(count), 0);
  for (std::size_t i = 0; i < angles_deg.size(); ++i) {
    sum[static_cast<std::size_t>(cluster[i])] += angles_deg[i];
    ++size[static_cast<std::size_t>(cluster[i])];
  }
  std::vector<int> merged(static_cast<std::size_t>(count), 0);
  double set_sum = 0.0;  // [deg] the readings of the set angle so far
  int set_count = 0, current = 0;
  for (std::size_t c = 0; c < merged.size(); ++c) {
    const double mean = sum[c] / size[c];
    if (set_count > 0 && std::abs(mean - set_sum / set_count) > kSetAngleStepDeg) {
      ++current;
      set_sum = 0.0;
      set_count = 0;
    }
    set_sum += sum[c];
    set_count += size[c];
    merged[c] = current;
  }
  std::vector<int> id(angles_deg.size());
  for (std::size_t i = 0; i < angles_deg.size(); ++i) id[i] = merged[static_cast<std::size_t>(cluster[i])];
  return id;
}

std::size_t Trial::size() const { return sweep.size() + rom.size() + tensile.size() + trajectory.size(); }

namespace {

[[noreturn]] void fail_at(const io::CsvTable& table, std::size_t row, const std::string& problem) {
  throw std::runtime_error(fmt::format("{}:{}: {}", table.source(), table.line_of(row), problem));
}

sim::MuscleIndex muscle_cell(const io::CsvTable& table, std::size_t row, int column) {
  const std::string& name = table.cell(row, column);
  if (const auto muscle = sim::muscle_from_name(name)) return *muscle;
  fail_at(table, row, fmt::format("muscle: '{}' is not flexor, extensor, ulnar or radial", name));
}

int integer_cell(const io::CsvTable& table, std::size_t row, int column) {
  if (column < 0) return 0;
  const int value = table.integer(row, column);
  if (value < 0) fail_at(table, row, fmt::format("{}: must be a count from 0", table.header()[column]));
  return value;
}

// A pressure cell [kPa] as pascals; the regulator range is checked against the device later, this only refuses
// what no fPAM holds.
double pressure_cell(const io::CsvTable& table, std::size_t row, int column) {
  const double kpa = table.number(row, column);
  if (kpa < 0.0 || kpa > 1000.0)
    fail_at(table, row, fmt::format("{}: {} kPa is outside 0..1000 kPa", table.header()[column], kpa));
  return kpa_to_pa(kpa);
}

// A measured pressure cell [kPa]: a sensor's zero may read a little below zero.
double measured_pressure_cell_kpa(const io::CsvTable& table, std::size_t row, int column) {
  const double kpa = table.number(row, column);
  if (kpa < -20.0 || kpa > 1000.0)
    fail_at(table, row, fmt::format("{}: {} kPa is outside -20..1000 kPa", table.header()[column], kpa));
  return kpa;
}

// How the wrist came to each held angle, in the log's order per muscle and repetition: the direction of the last
// change of set angle, kept while the angle is held (other pressures). A change is a reading beyond kSetAngleStepDeg
// of the held angle's mean so far, not a new cluster of all the readings: one jittered reading that clustered apart
// was read as a step out and back, a reversal that made a whole sweep "reached both ways", and a hysteresis fitted to
// the tensile test then contradicted that sweep (3 of the catalogue benchmark's 5 hysteresis data sets). Per
// repetition, so that a file sorted by angle with the repetitions side by side still gives each repetition's own
// direction; a repetition's first angle is 0 (not known). A muscle whose angles were all reached the same way keeps
// 0: one branch of the loop alone is a force scale, which the fPAM's parameters already fit, not evidence of
// hysteresis.
void set_sweep_motion(std::vector<SweepPoint>& sweep) {
  std::map<std::pair<int, int>, std::vector<std::size_t>> rows;  // per muscle and repetition, in the log's order
  for (std::size_t i = 0; i < sweep.size(); ++i) rows[{sweep[i].muscle, sweep[i].repetition}].push_back(i);
  for (const auto& [key, indices] : rows) {
    int motion = 0;
    double held_sum = 0.0;  // [deg] the readings of the angle held now
    int held_count = 0;
    for (std::size_t i : indices) {
      const double angle = units::rad_to_deg(sweep[i].angle);
      if (held_count > 0 && std::abs(angle - held_sum / held_count) > kSetAngleStepDeg) {
        motion = angle > held_sum / held_count ? 1 : -1;
        held_sum = 0.0;
        held_count = 0;
      }
      held_sum += angle;
      ++held_count;
      sweep[i].motion = motion;
    }
  }
  std::map<int, std::pair<bool, bool>> ways;  // per muscle: reached moving up, moving down
  for (const SweepPoint& s : sweep) {
    if (s.motion > 0) ways[s.muscle].first = true;
    if (s.motion < 0) ways[s.muscle].second = true;
  }
  for (SweepPoint& s : sweep) {
    if (!(ways[s.muscle].first && ways[s.muscle].second)) s.motion = 0;
  }
}

std::vector<Trial> sweep_trials(const experiments::TrialLog& log, Trial base) {
  const io::CsvTable& t = log.table;
  const int c_angle = t.column("angle_deg"), c_pressure = t.column("pressure_kpa"), c_torque = t.column("torque_nm");
  const int c_rep = t.find_column("repetition"), c_muscle = t.find_column("muscle");
  sim::MuscleIndex default_muscle = sim::kFlexor;
  if (log.header.config.contains("muscle") && log.header.config["muscle"].is_string()) {
    if (const auto m = sim::muscle_from_name(log.header.config["muscle"].get<std::string>())) default_muscle = *m;
  }
  base.kind = TrialKind::kTorqueSweep;
  for (std::size_t r = 0; r < t.row_count(); ++r) {
    base.sweep.push_back({.muscle = c_muscle >= 0 ? muscle_cell(t, r, c_muscle) : default_muscle,
                          .angle = deg_to_rad(t.number(r, c_angle)),
                          .pressure = pressure_cell(t, r, c_pressure),
                          .torque = t.number(r, c_torque),
                          .repetition = integer_cell(t, r, c_rep)});
  }
  set_sweep_motion(base.sweep);
  return {base};
}

std::vector<Trial> rom_trials(const experiments::TrialLog& log, Trial base) {
  const io::CsvTable& t = log.table;
  const int c_muscle = t.column("muscle"), c_pressure = t.column("pressure_kpa"), c_limit = t.column("limit_deg");
  const int c_rep = t.find_column("repetition");
  base.kind = TrialKind::kRangeOfMotion;
  for (std::size_t r = 0; r < t.row_count(); ++r) {
    base.rom.push_back({.muscle = muscle_cell(t, r, c_muscle),
                        .pressure = pressure_cell(t, r, c_pressure),
                        .limit = deg_to_rad(t.number(r, c_limit)),
                        .repetition = integer_cell(t, r, c_rep)});
  }
  return {base};
}

std::vector<Trial> tensile_trials(const experiments::TrialLog& log, Trial base) {
  const io::CsvTable& t = log.table;
  const int c_pressure = t.column("pressure_kpa"), c_eps = t.column("contraction"), c_force = t.column("force_n");
  const int c_direction = t.find_column("direction"), c_cycle = t.find_column("cycle");
  base.kind = TrialKind::kTensile;
  for (std::size_t r = 0; r < t.row_count(); ++r) {
    const double eps = t.number(r, c_eps);
    if (eps < -0.5 || eps >= 1.0)
      fail_at(t, r, fmt::format("contraction: {} is not a contraction ratio (-0.5..1)", eps));
    bool loading = true;
    if (c_direction >= 0) {
      const std::string& d = t.cell(r, c_direction);
      if (d != "loading" && d != "unloading")
        fail_at(t, r, fmt::format("direction: '{}' is not loading or unloading", d));
      loading = d == "loading";
    }
    base.tensile.push_back({.pressure = pressure_cell(t, r, c_pressure),
                            .contraction = eps,
                            .force = t.number(r, c_force),
                            .loading = loading,
                            .cycle = integer_cell(t, r, c_cycle)});
  }
  return {base};
}

std::vector<Trial> trajectory_trials(const experiments::TrialLog& log, Trial base) {
  const io::CsvTable& t = log.table;
  const int c_t = t.column("t_s"), c_fe = t.column("measured_fe_deg"), c_ur = t.column("measured_ur_deg");
  std::array<int, 4> c_cmd{};
  for (std::size_t m = 0; m < 4; ++m) c_cmd[m] = t.column(fmt::format("cmd_{}_kpa", control::kMuscleNames[m]));
  const int c_case = t.find_column("case");
  // Measured pressures are optional, but all four or none: a replay compares every muscle's regulator.
  std::array<int, 4> c_measured{};
  int measured_columns = 0;
  for (std::size_t m = 0; m < 4; ++m) {
    c_measured[m] = t.find_column(fmt::format("p_{}_kpa", control::kMuscleNames[m]));
    measured_columns += c_measured[m] >= 0 ? 1 : 0;
  }
  if (measured_columns != 0 && measured_columns != 4) {
    throw std::runtime_error(
        fmt::format("{}: has {} of the four measured-pressure columns p_<muscle>_kpa; give all "
                    "four (flexor, extensor, ulnar, radial) or none",
                    t.source(), measured_columns));
  }
  base.kind = TrialKind::kTrajectory;
  std::map<std::string, Trial> by_case;  // rows of several cases may interleave in a merged log
  std::vector<std::string> order;
  for (std::size_t r = 0; r < t.row_count(); ++r) {
    const std::string key = c_case >= 0 ? t.cell(r, c_case) : "0";
    auto [it, inserted] = by_case.try_emplace(key, base);
    if (inserted) {
      it->second.name = base.name + (c_case >= 0 ? ":case " + key : "");
      order.push_back(key);
    }
    TrajectorySample s{.t = t.number(r, c_t), .fe = deg_to_rad(t.number(r, c_fe)), .ur = deg_to_rad(t.number(r, c_ur))};
    for (std::size_t m = 0; m < 4; ++m) s.command_kpa[m] = units::pa_to_kpa(pressure_cell(t, r, c_cmd[m]));
    if (measured_columns == 4) {
      s.measured_kpa.emplace();
      for (std::size_t m = 0; m < 4; ++m) (*s.measured_kpa)[m] = measured_pressure_cell_kpa(t, r, c_measured[m]);
    }
    auto& samples = it->second.trajectory;
    if (!samples.empty() && !(s.t > samples.back().t)) {
      fail_at(t, r,
              fmt::format("t_s: {} does not follow {} (time must increase within a case)", s.t, samples.back().t));
    }
    if (samples.empty() && s.t < 0.0) fail_at(t, r, "t_s: a trajectory starts at t >= 0");
    samples.push_back(s);
  }
  std::vector<Trial> trials;
  for (const auto& key : order) {
    if (by_case.at(key).trajectory.size() < 10) {
      throw std::runtime_error(fmt::format("{}: case {} has {} rows; a trajectory needs at least 10", t.source(), key,
                                           by_case.at(key).trajectory.size()));
    }
    trials.push_back(std::move(by_case.at(key)));
  }
  return trials;
}

}  // namespace

std::vector<Trial> read_trials(const fs::path& sidecar, const std::string& name) {
  return trials_from_log(experiments::read_log(sidecar.parent_path(), sidecar.stem().string()), name,
                         sidecar.parent_path());
}

std::vector<Trial> trials_from_log(const experiments::TrialLog& log, const std::string& name, const fs::path& log_dir) {
  if (log.table.row_count() == 0) throw std::runtime_error(fmt::format("{}: no rows", log.table.source()));
  Trial base{.name = name, .file = log.table.source()};
  base.conventions = conventions_from_config(log.header.config, log_dir, log.table.source());
  const std::string& kind = log.header.kind;
  if (kind == "torque_validation" || kind == "torque_sweep") return sweep_trials(log, base);
  if (kind == "range_of_motion") return rom_trials(log, base);
  if (kind == "tensile") return tensile_trials(log, base);
  if (kind == "tracking" || kind == "trajectory") return trajectory_trials(log, base);
  throw std::runtime_error(
      fmt::format("{}: kind '{}' has no measurements a diagnosis compares (it reads "
                  "torque_validation, torque_sweep, range_of_motion, tensile, tracking, trajectory)",
                  log.table.source(), kind));
}

RealData load_real_data(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error(fmt::format("{}: not a directory of trial logs", dir.string()));
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file() && (entry.path().extension() == ".json" || entry.path().extension() == ".csv")) {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  RealData data;
  for (const fs::path& file : files) {
    const std::string name = fs::relative(file, dir).replace_extension().generic_string();
    if (file.extension() == ".csv") {
      // A run directory's other CSVs (model curves) sit beside its log; a lone CSV is a user's file not yet imported.
      const bool has_sidecar = fs::exists(fs::path(file).replace_extension(".json"));
      const bool beside_a_log = fs::exists(file.parent_path() / "trials.json");
      if (!has_sidecar && !beside_a_log) {
        data.problems.push_back({file.string(),
                                 "a CSV without its log sidecar (.json); convert it with "
                                 "`softwrist import --kind KIND FILE.csv --out DIR`"});
      }
      continue;
    }
    try {
      // Only sidecars of the log format are logs; summaries and bridge.json sit beside them.
      const auto json = nlohmann::json::parse(io::read_text_file(file), nullptr, /*allow_exceptions=*/false);
      if (!json.is_object() || json.value("format", "") != experiments::kLogFormat) continue;
      for (Trial& trial : read_trials(file, name)) data.trials.push_back(std::move(trial));
    } catch (const std::exception& e) {
      data.problems.push_back({file.string(), e.what()});
    }
  }
  return data;
}

}  // namespace softwrist::diagnosis
