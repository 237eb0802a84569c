#include "cli/diagnose_commands.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <set>

#include <unistd.h>

#include <fmt/format.h>

#include "cli/arguments.h"
#include "cli/independent_bench_command.h"
#include "diagnosis/benchmark.h"
#include "diagnosis/csv_import.h"
#include "diagnosis/diagnosis.h"
#include "diagnosis/diagnosis_report.h"
#include "diagnosis/synthetic_device.h"
#include "sim/device.h"

namespace softwrist::cli {
namespace {

// --effect-base, for diagnose and diagnose-bench (DiagnosisOptions::effect_base): its value, or a usage error.
diagnosis::EffectBase effect_base_named(const std::string& name) {
  if (name == "better") return diagnosis::EffectBase::kBetterOfBoth;
  if (name == "as-placed") return diagnosis::EffectBase::kAsPlaced;
  if (name == "within-tolerances") return diagnosis::EffectBase::kWithinTolerances;
  throw UsageError(fmt::format("--effect-base: '{}' is none of better, as-placed, within-tolerances", name));
}

// --routing-by, for diagnose and diagnose-bench (DiagnosisOptions::routing_by): its value, or a usage error.
diagnosis::RoutingBy routing_by_named(const std::string& name) {
  if (name == "best") return diagnosis::RoutingBy::kBestModel;
  if (name == "nominal") return diagnosis::RoutingBy::kNominalWithinTolerances;
  throw UsageError(fmt::format("--routing-by: '{}' is neither best nor nominal", name));
}

void add_routing_by_option(CLI::App& command, std::string& by) {
  command.add_option("--routing-by", by,
                     "Where the data leave the routing open, the held-out error that decides: best (each routing "
                     "diagnosed whole, the lower of its corrected model's and nominal-within-tolerances'; the "
                     "default) or nominal (each routing's nominal within its tolerances, fitted on the training part, "
                     "the effects then fitted with the one kept; experimental) (docs/diagnosis.md)");
}

void add_effect_base_option(CLI::App& command, std::string& base) {
  command.add_option("--effect-base", base,
                     "What each effect is fitted from: better (from both below, the fit that predicts the held-out "
                     "data better kept; the default), as-placed (the nominal as placed) or within-tolerances (the "
                     "nominal within its tolerances, the effect's own back at the nominal) (docs/diagnosis.md)");
}

namespace fs = std::filesystem;

struct DiagnoseOptions {
  std::string real, model, out;
  std::vector<std::string> effects;
  int jobs = 2;
  int bootstrap = 200;
  bool no_plots = false;
  std::string tolerances;  // a tolerance file
  bool no_tolerances = false;
  bool rank_beyond_tolerances = false;
  bool repeat_mean_test = false;
  std::string effect_base = "better";
  bool pressures_from_commands = false;
  std::string routing = "auto";
  std::string routing_by = "best";
};

void run_diagnose(const DiagnoseOptions& o, std::ostream& out, std::ostream& err) {
  if (o.jobs < 1) throw UsageError("--jobs must be >= 1");
  if (o.bootstrap < 20) throw UsageError("--bootstrap must be >= 20");
  diagnosis::DiagnosisOptions options{.jobs = o.jobs, .bootstrap = o.bootstrap};
  for (const std::string& name : o.effects) {
    const auto id = diagnosis::effect_from_name(name);
    if (!id) {
      std::vector<std::string> names;
      for (const auto& spec : diagnosis::effect_catalogue()) names.push_back(spec.name);
      throw UsageError(fmt::format("--effects: '{}' is not in the catalogue ({})", name, fmt::join(names, ", ")));
    }
    options.effects.push_back(*id);
  }
  if (o.no_tolerances && !o.tolerances.empty()) throw UsageError("--tolerances and --no-tolerances exclude each other");
  if (o.no_tolerances) options.tolerances = diagnosis::Tolerances::none();
  if (o.no_tolerances && o.rank_beyond_tolerances)
    throw UsageError("--rank-beyond-tolerances needs the tolerances; it excludes --no-tolerances");
  options.effect_base = effect_base_named(o.effect_base);
  if (o.no_tolerances && options.effect_base == diagnosis::EffectBase::kWithinTolerances)
    throw UsageError("--effect-base within-tolerances needs the tolerances; it excludes --no-tolerances");
  options.rank_beyond_tolerances = o.rank_beyond_tolerances;
  options.repeat_mean_test = o.repeat_mean_test;
  if (!o.tolerances.empty()) options.tolerances = diagnosis::read_tolerances(o.tolerances);
  if (o.routing != "auto") {
    options.routing = sim::parse_routing(o.routing);
    if (!options.routing) throw UsageError(fmt::format("--routing: '{}' is not auto, spatial or planar", o.routing));
  }
  options.routing_by = routing_by_named(o.routing_by);
  const sim::DeviceDescription nominal = sim::load_device(o.model);
  const auto start = std::chrono::steady_clock::now();
  diagnosis::RealData data = diagnosis::load_real_data(o.real);
  for (const auto& p : data.problems) err << fmt::format("skipped {}: {}\n", p.file, p.reason);
  diagnosis::ReplayEngine engine(sim::PluginSet::Default(), {},
                                 o.pressures_from_commands ? diagnosis::PressureSource::kCommands
                                                           : diagnosis::PressureSource::kMeasuredWhereLogged);
  const std::size_t problems_before = data.problems.size();
  const diagnosis::Diagnosis d = diagnosis::diagnose(std::move(data), nominal, engine, options);
  for (std::size_t i = problems_before; i < d.problems.size(); ++i) {
    err << fmt::format("skipped {}: {}\n", d.problems[i].file, d.problems[i].reason);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const fs::path dir = o.out.empty() ? fs::path(o.real) / "diagnosis" : fs::path(o.out);
  const auto report = diagnosis::write_diagnosis_report(d, dir, {.plots = !o.no_plots, .wall_s = wall});
  out << fmt::format("verdict: {} ({})\n", d.verdict, d.reason);
  const char* why = !d.routing_heldout_error.empty() ? " (diagnosed both ways: the better held-out fit)"
                    : !d.routing_heldout_error_nominal.empty()
                        ? " (its nominal within the tolerances predicts the held-out part better)"
                    : !d.routing_training_error.empty() ? " (the clearly lower training error as placed)"
                                                        : "";
  out << fmt::format("muscles routed {}{}\n", sim::to_string(d.routing), why);
  out << fmt::format("held-out error ({}): nominal {:.3f}, corrected {:.3f}\n", diagnosis::kErrorMetric,
                     d.heldout_nominal, d.heldout_corrected);
  const bool any_gap = std::any_of(d.trials.begin(), d.trials.end(), [](const auto& t) { return t.gap; });
  if (any_gap) {
    out << fmt::format(
        "the same over the trials with a significant gap: nominal {:.3f}, corrected {:.3f} (closed {:.1f} %)\n",
        d.gap_nominal, d.gap_corrected, 100.0 * d.gap_closed());
  } else {
    // Not "closed 0.0 %": there was no gap to close (a `none`, or an effect named from a pinned tolerance).
    out << "no trial has a significant gap (within the tolerances, where fitted): nothing to close\n";
  }
  out << "effect            shrink   95% CI            held-out after  params\n";
  for (const auto& f : d.effects) {
    if (!f.applicable) {
      out << fmt::format("{:<17} (no data it acts on)\n", f.name);
      continue;
    }
    std::vector<std::string> params;
    for (const auto& [name, value] : f.params) params.push_back(fmt::format("{}={:.4g}", name, value));
    out << fmt::format("{:<17} {:>6.1f}%  [{:>6.1f}, {:>6.1f}]%  {:>14.3f}  {}\n", f.name, 100 * f.shrink_fraction,
                       100 * f.ci_low, 100 * f.ci_high, f.heldout_error_after, fmt::join(params, " "));
  }
  out << fmt::format("{} ({} s)\n", report.json.string(), fmt::format("{:.1f}", wall));
  if (!report.page.empty()) out << report.page.string() << "\n";
}

struct ImportCommandOptions {
  std::string file, out;
  diagnosis::ImportOptions import;
};

struct SynthesizeOptions {
  std::string model, out;
  std::string mount_stiffness;  // K1,K2 in N/cm^2
  double dead_time_s = 0.0, imu_latency_s = 0.0, hysteresis = 0.0, wrist_radius_scale = 1.0;
  double stiffness_scale = 1.0, limit_stiffening_nm = 0.0, time_constant_s = -1.0, r0_scale = 1.0, eps_max_shift = 0.0;
  double second_order_time_s = 0.0;
  std::string imu_offset_deg;  // fe,ur
  double trajectory_s = 24.0;
  bool trajectory_steps = false;
  int repetitions = 3;
  bool no_measured_pressures = false;
  std::uint64_t seed = 1;
};

void run_synthesize(const SynthesizeOptions& o, std::ostream& out) {
  diagnosis::SyntheticDevice real{.device = sim::load_device(o.model)};
  sim::DeviceDescription& d = real.device;
  if (!o.mount_stiffness.empty()) {
    const auto k = parse_numbers(o.mount_stiffness, 2, "--mount-stiffness-n-per-cm2");
    if (k[0] <= 0 || k[1] <= 0) throw UsageError("--mount-stiffness-n-per-cm2: both stiffnesses must be > 0");
    d.mount_stiffness.forearm = k[0] * 1e4;  // the placement's law's shape (physics/mount_stretch.h) stays
    d.mount_stiffness.hand = k[1] * 1e4;
    d.stretch_mode = physics::StretchMode::kSelfConsistent;
  }
  if (!o.imu_offset_deg.empty()) {
    const auto v = parse_numbers(o.imu_offset_deg, 2, "--imu-offset-deg");
    real.imu_offset_fe_deg = v[0];
    real.imu_offset_ur_deg = v[1];
  }
  if (o.dead_time_s < 0 || o.dead_time_s > 1) throw UsageError("--dead-time-s must be within 0..1");
  if (o.imu_latency_s < 0 || o.imu_latency_s > 1) throw UsageError("--imu-latency-s must be within 0..1");
  if (!(o.hysteresis >= 0 && o.hysteresis < 0.5)) throw UsageError("--hysteresis must be >= 0 and < 0.5");
  if (o.trajectory_s < 1 || o.trajectory_s > 600) throw UsageError("--trajectory-s must be within 1..600");
  if (o.repetitions < 1 || o.repetitions > 20) throw UsageError("--repetitions must be within 1..20");
  real.regulator_dead_time = o.dead_time_s;
  real.imu_latency = o.imu_latency_s;
  real.hysteresis = o.hysteresis;
  // The effects that live in the device description, applied here by editing it.
  if (!(o.wrist_radius_scale > 0) || !(o.stiffness_scale > 0) || !(o.r0_scale > 0)) {
    throw UsageError("--wrist-radius-scale, --passive-stiffness-scale and --r0-scale must be > 0");
  }
  for (auto& m : d.muscles) m.wrist_radius *= o.wrist_radius_scale;
  d.wrist.stiffness_fe *= o.stiffness_scale;
  d.wrist.stiffness_ur *= o.stiffness_scale;
  d.wrist.limit_stiffening.torque += o.limit_stiffening_nm;
  if (o.time_constant_s > 0) d.regulator.time_constant = o.time_constant_s;
  d.regulator.second_order_time = o.second_order_time_s;  // checked with the description below
  d.fpam = d.fpam.scaled(o.r0_scale, o.eps_max_shift);
  sim::parse_device(sim::device_to_json(d), "the synthesized device");  // validates the edited description
  diagnosis::write_synthetic_data(real,
                                  {.measured_pressures = !o.no_measured_pressures,
                                   .repetitions = o.repetitions,
                                   .trajectory_s = o.trajectory_s,
                                   .trajectory_steps = o.trajectory_steps,
                                   .seed = o.seed},
                                  o.out);
  std::ofstream(fs::path(o.out) / "real_device.json") << sim::device_to_json(d);
  out << fmt::format(
      "{}: torque_sweep, range_of_motion, tensile, trajectory (the device as simulated: "
      "real_device.json)\n",
      o.out);
}

// Where the time went: the simulated replays (cached ones not counted), their wall time summed over threads.
nlohmann::json replays_json(const diagnosis::ReplayStats& s) {
  return {{"trajectories", s.trajectories}, {"trajectory_s", s.trajectory_s}, {"trajectory_sim_s", s.trajectory_sim_s},
          {"settles", s.settles},           {"settle_s", s.settle_s},         {"cache_hits", s.cache_hits}};
}

struct DiagnoseBenchOptions {
  bool json = false;
  double trajectory_s = 72.0;
  int jobs = 2;
};

// The paper-sized data set: the torque sweep of experiments/torque_validation.json (8 angles, 5 pressures, 3
// repetitions), a range of motion (4 muscles, 3 repetitions), a tensile test and a 72 s trajectory (three 24 s
// periods, as Section Spatial trajectory tracking), from the paper's device; the nominal model withholds its
// stretching (the paper's case).
void run_diagnose_bench(const DiagnoseBenchOptions& o, std::ostream& out) {
  if (o.jobs < 1) throw UsageError("--jobs must be >= 1");
  if (o.trajectory_s < 1 || o.trajectory_s > 600) throw UsageError("--trajectory-s must be within 1..600");
  const fs::path dir = fs::temp_directory_path() / fmt::format("softwrist_bench_diagnose_{}", ::getpid());
  fs::remove_all(dir);
  const auto t0 = std::chrono::steady_clock::now();
  diagnosis::write_synthetic_data({.device = sim::paper_device()}, {.trajectory_s = o.trajectory_s}, dir);
  const auto t1 = std::chrono::steady_clock::now();
  sim::DeviceDescription nominal = sim::paper_device();
  nominal.stretch_mode = physics::StretchMode::kNone;
  diagnosis::ReplayEngine engine(sim::PluginSet::Default());
  diagnosis::RealData data = diagnosis::load_real_data(dir);
  std::size_t points = 0;
  for (const auto& t : data.trials) points += t.size();
  const diagnosis::Diagnosis d = diagnosis::diagnose(std::move(data), nominal, engine, {.jobs = o.jobs});
  const auto t2 = std::chrono::steady_clock::now();
  fs::remove_all(dir);
  int evaluations = 0;
  for (const auto& f : d.effects) evaluations += f.evaluations;
  for (const auto& f : d.combination) evaluations += f.evaluations;
  const double wall = std::chrono::duration<double>(t2 - t1).count();
  const nlohmann::json result = {{"wall_s", wall},
                                 {"synthesize_s", std::chrono::duration<double>(t1 - t0).count()},
                                 {"target_s", 10.0},
                                 {"jobs", o.jobs},
                                 {"trials", d.trials.size()},
                                 {"measurements", points},
                                 {"model_evaluations", evaluations},
                                 {"tolerance_evaluations", d.tolerance.evaluations},
                                 {"replays", replays_json(engine.stats())},
                                 {"verdict", d.verdict}};
  if (o.json) {
    out << result.dump(2) << "\n";
    return;
  }
  out << fmt::format(
      "diagnosis of the paper-sized data set ({} trials, {} measurements, {} model evaluations, {} "
      "jobs): {:.2f} s (target <= 10 s, issue 22); verdict {}\n",
      d.trials.size(), points, evaluations, o.jobs, wall, d.verdict);
  const diagnosis::ReplayStats s = engine.stats();
  out << fmt::format(
      "  replays: {} trajectories ({:.0f} s simulated) in {:.1f} s, {} range-of-motion settles in {:.1f} s (summed "
      "over threads), {} from the cache; the tolerance fit {} evaluations\n",
      s.trajectories, s.trajectory_sim_s, s.trajectory_s, s.settles, s.settle_s, s.cache_hits, d.tolerance.evaluations);
}

struct DiagnoseBenchmarkOptions {
  std::string generator = "catalogue";
  IndependentBenchArguments independent;  // --generator independent
  int seeds = 0;                          // 0: the generator's default (catalogue 5, independent 20)
  std::uint64_t first_seed = 1;
  int jobs = 2;
  std::vector<std::string> cases;
  double trajectory_s = 24.0;
  std::string keep;
  double variation = 1.0;
  std::string effect_base = "better";
  std::string routing_by = "best";  // independent only
  bool json = false;
};

std::string percent(double v) { return std::isfinite(v) ? fmt::format("{:.1f} %", 100.0 * v) : "-"; }

// The withheld-effect benchmark (diagnosis/benchmark.h) on the paper's device.
void run_catalogue_benchmark(const DiagnoseBenchmarkOptions& o, std::ostream& out, std::ostream& err) {
  if (o.seeds < 1 || o.seeds > 1000) throw UsageError("--seeds must be within 1..1000");
  if (o.jobs < 1) throw UsageError("--jobs must be >= 1");
  if (o.trajectory_s < 4 || o.trajectory_s > 600) throw UsageError("--trajectory-s must be within 4..600");
  const auto names = diagnosis::bench_case_names();
  for (const auto& c : o.cases) {
    if (std::find(names.begin(), names.end(), c) == names.end()) {
      throw UsageError(fmt::format("--cases: '{}' is not a benchmark case ({})", c, fmt::join(names, ", ")));
    }
  }
  diagnosis::BenchOptions options{.seeds = o.seeds, .first_seed = o.first_seed, .jobs = o.jobs, .cases = o.cases};
  options.plan.trajectory_s = o.trajectory_s;
  options.diagnosis.effect_base = effect_base_named(o.effect_base);
  if (!(o.variation >= 0.0 && o.variation <= 10.0)) throw UsageError("--variation must be within 0..10");
  options.variation = o.variation;
  options.keep = !o.keep.empty();
  options.scratch = options.keep ? fs::path(o.keep)
                                 : fs::temp_directory_path() / fmt::format("softwrist_diagnose_bench_{}", ::getpid());
  if (!o.json) {
    err << fmt::format("{} cases x {} seeds and the paper's case on {} jobs...\n",
                       o.cases.empty() ? names.size() : o.cases.size(), o.seeds, o.jobs);
  }
  diagnosis::BenchResult result;
  try {
    result = diagnosis::run_benchmark(sim::paper_device(), options);
  } catch (...) {
    if (!options.keep) fs::remove_all(options.scratch);
    throw;
  }
  if (!options.keep) fs::remove_all(options.scratch);
  if (o.json) {
    out << diagnosis::to_json(result).dump(2) << "\n";
    return;
  }
  std::set<std::string> verdicts;
  for (const auto& [injected, row] : result.confusion) {
    for (const auto& [verdict, count] : row) verdicts.insert(verdict);
  }
  out << "confusion (rows: injected, columns: verdict)\n" << fmt::format("{:<15}", "");
  for (const auto& v : verdicts) out << fmt::format(" {:>14}", v);
  out << fmt::format(" {:>12}\n", "mean shrink");
  for (const auto& name : names) {
    if (!result.confusion.contains(name)) continue;
    out << fmt::format("{:<15}", name);
    for (const auto& v : verdicts) {
      const auto& row = result.confusion.at(name);
      out << fmt::format(" {:>14}", row.contains(v) ? std::to_string(row.at(v)) : ".");
    }
    double shrink = 0.0;
    int n = 0;
    for (const auto& r : result.runs) {
      if (r.injected != name) continue;
      shrink += r.shrink_fraction;
      ++n;
    }
    out << fmt::format(" {:>12}\n", percent(shrink / n));
  }
  const auto line = [&](const char* what, double value, double target) {
    out << fmt::format("{:<42} {:>8}  (target >= {:.0f} %){}\n", what, percent(value), 100.0 * target,
                       std::isfinite(value) ? (value >= target ? "" : "  MISSED") : "");
  };
  line("top-1 accuracy, single catalogue effects", result.top1_accuracy, diagnosis::kTop1Target);
  line("held-out gap closed, single catalogue effects", result.mean_shrink_fraction, diagnosis::kShrinkTarget);
  line("'none' on the no-effect case", result.none_correct_rate, diagnosis::kNoneTarget);
  line(fmt::format("'unexplained' on the outside case ({})", diagnosis::kOutsideEffect).c_str(),
       result.unexplained_correct_rate, diagnosis::kUnexplainedTarget);
  if (result.paper_case) {
    const auto& p = *result.paper_case;
    out << fmt::format(
        "paper's case (stretching withheld): verdict {}, torque MAE {:.3f} -> {:.3f} N m (x{:.1f}; the "
        "paper: 1.111 -> 0.283, x3.9)\n",
        p.verdict, p.torque_mae_before_nm, p.torque_mae_after_nm, p.torque_mae_before_nm / p.torque_mae_after_nm);
  }
  out << fmt::format("{} diagnoses in {:.1f} s\n", result.runs.size() + (result.paper_case ? 1 : 0), result.wall_s);
}

// The shared options go to the generator chosen; the independent generator's own options are refused with the
// catalogue's and the catalogue's (--variation) with the independent one.
void run_diagnose_benchmark(DiagnoseBenchmarkOptions o, const CLI::App& command, std::ostream& out, std::ostream& err) {
  const bool independent = o.generator == "independent";
  if (!independent && o.generator != "catalogue")
    throw UsageError(fmt::format("--generator: '{}' is neither catalogue nor independent", o.generator));
  for (const char* only :
       {"--shard", "--out", "--merge", "--calibrate", "--redecide", "--forms", "--no-pairs", "--min-level",
        "--torque-rig", "--prototype", "--rank-beyond-tolerances", "--repeat-mean-test", "--routing-by"}) {
    if (!independent && command.count(only) > 0)
      throw UsageError(fmt::format("{} needs --generator independent", only));
  }
  if (independent && command.count("--variation") > 0) throw UsageError("--variation is the catalogue generator's");
  if (independent && command.count("--cases") > 0) throw UsageError("--cases is the catalogue's; use --forms");
  if (!independent) {
    if (o.seeds == 0) o.seeds = 5;
    run_catalogue_benchmark(o, out, err);
    return;
  }
  IndependentBenchArguments& a = o.independent;
  if (o.seeds != 0) a.seeds = o.seeds;
  a.first_seed = o.first_seed;
  a.jobs = o.jobs;
  a.effect_base = effect_base_named(o.effect_base);
  a.routing_by = routing_by_named(o.routing_by);
  if (command.count("--trajectory-s") > 0) a.trajectory_s = o.trajectory_s;
  a.keep = o.keep;
  a.json = o.json;
  run_independent_bench(a, out, err);
}

}  // namespace

void add_diagnose_bench(CLI::App& bench, std::ostream& out) {
  auto o = std::make_shared<DiagnoseBenchOptions>();
  auto* command = bench.add_subcommand(
      "diagnose", "Wall time of one full gap diagnosis of the paper-sized data set (synthesized first, not timed)");
  command->add_flag("--json", o->json,
                    "Print {wall_s, synthesize_s, trials, measurements, model_evaluations, tolerance_evaluations, "
                    "replays, verdict}");
  command->add_option("--trajectory-s", o->trajectory_s, "Length of the trajectory trial (default 72 s)");
  command->add_option(
      "--jobs", o->jobs,
      "Effects fitted in parallel; above 1, beside the tolerance fit, each on this many threads (default 2)");
  command->callback([o, &out] { run_diagnose_bench(*o, out); });
}

// softwrist import: the user's CSV and what they state of how it was measured (docs/diagnosis.md, "Conventions").
void add_import_command(CLI::App& app, std::ostream& out) {
  auto i = std::make_shared<ImportCommandOptions>();
  auto* import =
      app.add_subcommand("import", "A CSV of your own measurements as a trial log (units in the column names)");
  import->add_option("file", i->file, "The CSV")->required();
  import->add_option("--kind", i->import.kind, "torque-sweep, rom, tensile or trajectory")->required();
  import->add_option("--out", i->out, "Directory of the log")->required();
  import->add_flag("--hand-supported", i->import.hand_supported, "A table carried the hand (--posture hand_supported)");
  import->add_option("--posture", i->import.posture,
                     "hand_supported, gravity_fe (forearm palm down: the hand's weight flexes) or gravity_ur "
                     "(thumb up: the weight deviates ulnarly; the default)");
  import->add_option("--torque-includes", i->import.torque_includes,
                     "Torque sweeps: what the sensor reads, muscle (default), muscle+passive_wrist, "
                     "muscle+passive_wrist+hand_weight, muscle+hand_weight, or baseline_subtracted");
  import->add_flag("--angles-zeroed", i->import.angles_zeroed, "The angles were zeroed at the trial's start");
  import->add_option("--angle-resolution-deg", i->import.angle_resolution_deg,
                     "The angle sensor's step (a BNO055: 0.0625)");
  import->add_option("--model", i->import.placement,
                     "The placement file of the rig the data came from (default: diagnose's --model)");
  import->add_option("--muscle", i->import.muscle,
                     "Torque sweeps without a muscle column: the muscle (default flexor)");
  import->add_flag("--overwrite", i->import.overwrite, "Replace a log already in --out");
  import->callback([i, &out] {
    const auto result = diagnosis::import_csv(i->file, i->out, i->import);
  out << fmt::format("{} ({} rows)\n", result.log.string(), result.rows);
});
}  // namespace softwrist::cli

namespace {

// softwrist diagnose-bench: the withheld-effect benchmark, on either generator.
void add_diagnose_bench_command(CLI::App& app, std::ostream& out, std::ostream& err) {
  auto b = std::make_shared<DiagnoseBenchmarkOptions>();
  auto* bench = app.add_subcommand(
      "diagnose-bench",
      "The diagnosis judged on data whose cause it is not told: each catalogue effect, none, and one "
      "outside the catalogue, injected at random magnitudes (docs/diagnosis.md)");
  bench->add_option(
      "--generator", b->generator,
      "catalogue (softwrist's own synthetic device, the default) or independent (src/independent_device)");
  bench->add_option("--seeds", b->seeds, "Data sets per case (default 5; independent: 20)");
  bench->add_option("--first-seed", b->first_seed, "Seed of the first data set (default 1)");
  bench->add_option("--jobs", b->jobs, "Data sets diagnosed in parallel (default 2)");
  bench->add_option("--cases", b->cases, "Only these cases (default all)")->delimiter(',');
  bench->add_option("--trajectory-s", b->trajectory_s,
                    "Length of each data set's trajectory (default 24 s; independent: 12 s)");
  bench->add_option("--variation", b->variation,
                    "Scale of the device-to-device variations (default 1: the assumed tolerances, docs/diagnosis.md)");
  bench->add_option("--keep", b->keep, "Keep each data set and its diagnosis.json under this directory");
  bench->add_flag("--json", b->json,
                  "Print {top1_accuracy, mean_shrink_fraction, none_correct_rate, unexplained_correct_rate, "
                  "confusion, runs, paper_case, wall_s}");
  bench->add_option("--forms", b->independent.forms, "independent: only these forms (default every form)")
      ->delimiter(',');
  bench->add_flag(
      "--no-pairs", [b](std::int64_t) { b->independent.pairs = false; },
      "independent: without the pairs of two effects");
  bench->add_option("--min-level", b->independent.min_level,
                    "independent: each effect's level is drawn log-uniform in [this, 1] (default 0.2)");
  add_effect_base_option(*bench, b->effect_base);
  bench->add_flag("--rank-beyond-tolerances", b->independent.rank_beyond_tolerances,
                  "independent: diagnose as diagnose --rank-beyond-tolerances does (experimental)");
  bench->add_flag("--repeat-mean-test", b->independent.repeat_mean_test,
                  "independent: diagnose as diagnose --repeat-mean-test does (experimental)");
  add_routing_by_option(*bench, b->routing_by);
  bench->add_option("--shard", b->independent.shard, "independent: run shard K/N of the cases (default 1/1)");
  bench->add_option("--out", b->independent.out, "independent: also write the summary with its runs to this file");
  bench->add_option("--merge", b->independent.merge, "independent: merge these --out files instead of running");
  bench->add_flag("--redecide", b->independent.redecide,
                  "independent, with --merge: decide each run again at this build's decision settings, from the "
                  "verdicts its grid holds (runs diagnosed by an earlier build)");
  bench->add_option("--calibrate", b->independent.calibrate,
                    "independent: choose the verdict's decision settings from these runs (calibration seeds, apart "
                    "from the reported ones) and write the record to this file (experiments/diagnosis_calibration/)");
  bench->add_option("--torque-rig", b->independent.torque_rig,
                    "independent: the torque rig's placement (default experiments/independent_device/torque_rig.json)");
  bench->add_option("--prototype", b->independent.prototype,
                    "independent: the prototype's placement (default experiments/independent_device/prototype.json)");
  bench->callback([b, bench, &out, &err] { run_diagnose_benchmark(*b, *bench, out, err); });
}

}  // namespace

void add_diagnose_commands(CLI::App& app, std::ostream& out, std::ostream& err) {
  auto d = std::make_shared<DiagnoseOptions>();
  auto* diagnose = app.add_subcommand(
      "diagnose",
      "Where and why real trials differ from the model: localisation, the catalogue's effects fitted on "
      "training data and scored on held-out data, a verdict (docs/diagnosis.md)");
  diagnose->add_option("--real", d->real, "Directory of trial logs (hardware trials, imports, runs)")->required();
  diagnose->add_option("--model", d->model, "Placement file of the nominal model")->required();
  diagnose->add_option("--out", d->out, "Output directory (default REAL/diagnosis)");
  diagnose->add_option("--effects", d->effects, "Only these catalogue effects (default all)")->delimiter(',');
  diagnose->add_option(
      "--jobs", d->jobs,
      "Effects fitted in parallel; above 1, beside the tolerance fit, each on this many threads (default 2)");
  diagnose->add_option("--bootstrap", d->bootstrap, "Bootstrap resamples of the held-out units (default 200)");
  diagnose->add_option("--tolerances", d->tolerances,
                       "JSON file: how well the nominal placement is known (docs/diagnosis.md, Tolerances)");
  diagnose->add_flag("--no-tolerances", d->no_tolerances, "Measure the gap from the nominal exactly as placed");
  diagnose->add_flag("--rank-beyond-tolerances", d->rank_beyond_tolerances,
                     "Experimental: rank the effects fitted on top of the nominal within its tolerances, and decide "
                     "there (docs/diagnosis.md)");
  diagnose->add_flag("--repeat-mean-test", d->repeat_mean_test,
                     "Experimental: a repeated task's repetitions have a gap also where their mean does "
                     "(docs/diagnosis.md)");
  add_effect_base_option(*diagnose, d->effect_base);
  diagnose->add_flag("--pressures-from-commands", d->pressures_from_commands,
                     "Replay trajectories from their commands through the simulated regulators even where the log "
                     "has the measured pressures (by default those drive the muscles; docs/diagnosis.md)");
  diagnose->add_option("--routing", d->routing,
                       "How the model routes the muscles: auto (whichever of spatial and planar replays the training "
                       "part better; the default), spatial or planar (docs/diagnosis.md)");
  add_routing_by_option(*diagnose, d->routing_by);
  diagnose->add_flag("--no-plots", d->no_plots, "Without plots (no python3-matplotlib needed)");
  diagnose->callback([d, &out, &err] { run_diagnose(*d, out, err); });

  add_import_command(app, out);

  auto s = std::make_shared<SynthesizeOptions>();
  auto* synth = app.add_subcommand(
      "synthesize",
      "\"Real\" data from a simulated device with effects injected: a torque sweep, range of motion, "
      "tensile test and trajectory, for trying the diagnosis");
  synth->add_option("--model", s->model, "Placement file of the device before the effects")->required();
  synth->add_option("--out", s->out, "Output directory")->required();
  synth->add_option("--mount-stiffness-n-per-cm2", s->mount_stiffness, "K1,K2: the mounts stretch (self-consistent)");
  synth->add_option("--dead-time-s", s->dead_time_s, "Regulator dead time");
  synth->add_option("--time-constant-s", s->time_constant_s, "Regulator time constant");
  synth->add_option("--second-order-time-s", s->second_order_time_s,
                    "Regulator's second time tau2: tau2^2 p'' + tau p' + p = u (default 0, first order)");
  synth->add_option("--imu-offset-deg", s->imu_offset_deg, "fe,ur offset of the IMU pair");
  synth->add_option("--imu-latency-s", s->imu_latency_s, "IMU latency");
  synth->add_option("--hysteresis", s->hysteresis,
                    "The fabric's hysteresis h: tensile force x (1 +- h) loading/unloading, and its state in MuJoCo");
  synth->add_option("--wrist-radius-scale", s->wrist_radius_scale, "Every wrist radius times this");
  synth->add_option("--passive-stiffness-scale", s->stiffness_scale, "The relaxed wrist's stiffness times this");
  synth->add_option("--limit-stiffening-nm", s->limit_stiffening_nm,
                    "Added to the relaxed wrist's stiffening torque at its limits [N m]");
  synth->add_option("--r0-scale", s->r0_scale, "The fPAM's r0 times this");
  synth->add_option("--eps-max-shift", s->eps_max_shift, "Added to the fPAM's eps_max");
  synth->add_option("--trajectory-s", s->trajectory_s, "Length of the trajectory trial (default 24 s)");
  synth->add_flag("--trajectory-steps", s->trajectory_steps,
                  "The trajectory's commands in steps every 1.5 s instead of sinusoids");
  synth->add_option("--repetitions", s->repetitions,
                    "Repetitions of sweeps, range of motion, tensile cycles (default 3)");
  synth->add_option("--seed", s->seed, "Noise seed (default 1)");
  synth->add_flag("--no-measured-pressures", s->no_measured_pressures,
                  "The trajectory without the regulators' measured pressures (p_<muscle>_kpa)");
  synth->callback([s, &out] { run_synthesize(*s, out); });

  add_diagnose_bench_command(app, out, err);
}

}  // namespace softwrist::cli
