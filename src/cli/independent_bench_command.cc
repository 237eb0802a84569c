#include "cli/independent_bench_command.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <unistd.h>

#include <fmt/format.h>

#include "cli/arguments.h"
#include "diagnosis_bench/independent_benchmark.h"
#include "experiments/runner.h"
#include "io/json_reader.h"
#include "io/text_file.h"

namespace softwrist::cli {
namespace {

namespace fs = std::filesystem;
namespace db = diagnosis_bench;

std::string rate_text(const nlohmann::json& counts) {
  if (counts["cases"] == 0) return "- (no cases)";
  return fmt::format("{:.1f} % ({} of {}; Wilson 95 % {:.1f}-{:.1f} %)", 100.0 * counts["rate"].get<double>(),
                     counts["right"].get<int>(), counts["cases"].get<int>(), 100.0 * counts["ci95"][0].get<double>(),
                     100.0 * counts["ci95"][1].get<double>());
}

void print_summary(const nlohmann::json& s, std::ostream& out) {
  for (const auto& r : s["runs"]) {
    const std::string also = r["also_effects"].empty() ? "" : fmt::format(" also {}", r["also_effects"].dump());
    out << fmt::format(
        "{:<44} seed {:>3}: expected {:<14} verdict {:<14}{} {} ({:.1f} noise units; leading {} "
        "{:.0f} %){}\n",
        r["case"].get<std::string>(), r["seed"].get<std::uint64_t>(), r["expected"].get<std::string>(),
        r["verdict"].get<std::string>(), also, r["verdict"] == r["expected"] && r["error"] == "" ? "right" : "WRONG",
        r["magnitude_noise_units"].get<double>(), r["leading_effect"].get<std::string>(),
        100.0 * r["explained_fraction"].get<double>(),
        r["error"] == "" ? "" : " error: " + r["error"].get<std::string>());
  }
  const auto& c = s["counts"];
  out << fmt::format("top-1, single catalogue forms        {}  (target >= 90 %, lower bound >= 80 %)\n",
                     rate_text(c["single"]));
  out << fmt::format("'none' on the nominal device         {}  (target >= 90 %)\n", rate_text(c["none"]));
  out << fmt::format("'unexplained' on outside forms       {}  (target >= 80 %)\n", rate_text(c["outside"]));
  out << fmt::format("pairs: the larger effect named       {}  (target >= 80 %)\n", rate_text(c["pairs"]));
  if (!s["mean_shrink_fraction"].is_null())
    out << fmt::format("gap closed, single catalogue forms   {:.1f} %  (target >= 70 %)\n",
                       100.0 * s["mean_shrink_fraction"].get<double>());
  out << "detection curve (single catalogue forms, top-1 by the effect's size in noise units):\n";
  for (const auto& band : s["detection_curve"]) {
    const std::string to =
        band["to_noise_units"].is_null() ? "inf" : fmt::format("{:g}", band["to_noise_units"].get<double>());
    out << fmt::format("  {:>4g}-{:<4} {}\n", band["from_noise_units"].get<double>(), to, rate_text(band));
  }
  if (c["errors"] != 0) out << fmt::format("{} cases could not be run (see their error)\n", c["errors"].get<int>());
}

std::vector<db::IndependentRun> merged_runs(const std::vector<std::string>& files) {
  std::vector<db::IndependentRun> runs;
  for (const std::string& file : files) {
    const nlohmann::json summary = io::parse_json(io::read_text_file(file), file);
    for (auto& run : db::runs_from_json(summary, file)) runs.push_back(std::move(run));
  }
  return runs;
}

db::IndependentBenchOptions bench_options(const IndependentBenchArguments& a) {
  if (a.seeds < 1 || a.seeds > 1000) throw UsageError("--seeds must be within 1..1000");
  if (a.jobs < 1) throw UsageError("--jobs must be >= 1");
  if (a.trajectory_s < 4 || a.trajectory_s > 600) throw UsageError("--trajectory-s must be within 4..600");
  if (!(a.min_level > 0.0 && a.min_level <= 1.0)) throw UsageError("--min-level must be within (0, 1]");
  db::IndependentBenchOptions o{.forms = a.forms,
                                .seeds = a.seeds,
                                .first_seed = a.first_seed,
                                .trajectory_s = a.trajectory_s,
                                .min_level = a.min_level,
                                .jobs = a.jobs};
  if (!a.pairs) o.pairs.clear();
  o.diagnosis.effect_base = a.effect_base;
  o.diagnosis.rank_beyond_tolerances = a.rank_beyond_tolerances;
  o.diagnosis.repeat_mean_test = a.repeat_mean_test;
  o.diagnosis.routing_by = a.routing_by;
  try {
    std::tie(o.shard_index, o.shard_count) = experiments::parse_shard(a.shard);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--shard: ") + e.what());
  }
  o.rigs = {{"torque_rig", a.torque_rig}, {"prototype", a.prototype}};
  for (const auto& [rig, file] : o.rigs) {
    if (!fs::exists(file))
      throw UsageError(
          fmt::format("--{}: no placement file {}", rig == "prototype" ? "prototype" : "torque-rig", file.string()));
  }
  o.keep = !a.keep.empty();
  o.scratch =
      o.keep ? fs::path(a.keep) : fs::temp_directory_path() / fmt::format("softwrist_indep_bench_{}", ::getpid());
  return o;
}

// The decision settings this build decides with (DiagnosisOptions' defaults).
db::DecisionSettings build_settings() { return db::decision_settings(diagnosis::DiagnosisOptions{}); }

// The decision settings chosen from `runs` (db::calibrate_decisions), against the ones this build decides with.
void write_calibration(const std::vector<db::IndependentRun>& runs, const std::string& file, std::ostream& err) {
  const db::DecisionSettings current = build_settings();
  nlohmann::json record;
  try {
    record = db::calibrate_decisions(runs, current);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--calibrate: ") + e.what());
  }
  std::ofstream record_file(file);
  if (!(record_file << record.dump(2) << "\n"))
    throw std::runtime_error(fmt::format("--calibrate: cannot write {}", file));
  const nlohmann::json& c = record["chosen"];
  err << fmt::format(
      "calibration over {} cases: explained_fraction {:g}, pair_share {:g}, contradiction_gap {:g} (mean rate {:.3f}); "
      "this build decides with {:g}, {:g}, {:g}; the record: {}\n",
      record["cases"].get<int>(), c["explained_fraction"].get<double>(), c["pair_share"].get<double>(),
      c["contradiction_gap"].get<double>(), c["objective"].get<double>(), current.explained_fraction,
      current.pair_share, current.contradiction_gap, file);
}

}  // namespace

void run_independent_bench(const IndependentBenchArguments& a, std::ostream& out, std::ostream& err) {
  std::vector<db::IndependentRun> runs;
  if (!a.merge.empty()) {
    runs = merged_runs(a.merge);
    if (a.redecide) {
      try {
        db::redecide_runs(runs, build_settings());
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--redecide: ") + e.what());
      }
    }
  } else {
    if (a.redecide) throw UsageError("--redecide needs --merge");
    const db::IndependentBenchOptions o = bench_options(a);
    try {
      if (!a.json)
        err << fmt::format("{} data sets (shard {}) on {} jobs...\n", db::independent_cases(o).size(), a.shard, a.jobs);
      runs = db::run_independent_benchmark(o);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    if (!o.keep) fs::remove_all(o.scratch);
  }
  nlohmann::json summary;
  try {
    summary = db::summarize(runs);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (!a.out.empty()) std::ofstream(a.out) << summary.dump(2) << "\n";
  if (!a.calibrate.empty()) write_calibration(runs, a.calibrate, err);
  if (a.json) {
    out << summary.dump(2) << "\n";
  } else {
    print_summary(summary, out);
  }
}

}  // namespace softwrist::cli
