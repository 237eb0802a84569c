#include "diagnosis_bench/independent_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <set>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "common/parallel_for.h"
#include "diagnosis/csv_import.h"
#include "diagnosis/real_data.h"
#include "diagnosis_bench/wilson.h"
#include "independent_device/dataset.h"
#include "io/json_reader.h"
#include "io/text_file.h"
#include "sim/device.h"

namespace softwrist::diagnosis_bench {
namespace {

namespace fs = std::filesystem;
constexpr const char* kOutsidePrefix = "outside:";

const independent::FormInfo& form_info(const std::string& form) {
  for (const auto& f : independent::effect_forms()) {
    if (f.name == form) return f;
  }
  throw std::invalid_argument(
      fmt::format("'{}' is not a form of the independent device (softwrist generate "
                  "--list-forms)",
                  form));
}

// The label a verdict should give for one form alone.
std::string expected_label(const std::string& form) {
  const std::string& label = form_info(form).label;
  return label.starts_with(kOutsidePrefix) ? "unexplained" : label;
}

CaseCategory category_of(const IndependentCase& c) {
  if (c.forms.empty()) return CaseCategory::kNone;
  if (c.forms.size() == 2) return CaseCategory::kPair;
  return form_info(c.forms[0]).label.starts_with(kOutsidePrefix) ? CaseCategory::kOutside : CaseCategory::kSingle;
}

const char* category_name(CaseCategory c) {
  switch (c) {
    case CaseCategory::kNone:
      return "none";
    case CaseCategory::kSingle:
      return "single";
    case CaseCategory::kOutside:
      return "outside";
    case CaseCategory::kPair:
      return "pair";
  }
  return "";
}

// Each effect's level, log-uniform in [min_level, 1], from the case's seed and form (the same whatever the shard).
std::vector<double> draw_levels(const IndependentCase& c, double min_level) {
  std::vector<double> levels;
  for (const std::string& form : c.forms) {
    std::uint64_t form_hash = 1469598103934665603ull;  // FNV-1a: the same on every platform, unlike std::hash
    for (unsigned char ch : form) form_hash = (form_hash ^ ch) * 1099511628211ull;
    std::seed_seq seq{c.seed, form_hash, std::uint64_t{20}};
    std::mt19937_64 rng(seq);
    const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    levels.push_back(min_level * std::pow(1.0 / min_level, u));
  }
  return levels;
}

std::vector<independent::EffectSpec> effect_specs(const std::vector<std::string>& forms,
                                                  const std::vector<double>& levels) {
  std::vector<independent::EffectSpec> specs;
  for (std::size_t i = 0; i < forms.size(); ++i) specs.push_back({.form = forms[i], .level = levels[i]});
  return specs;
}

// Every file of a generated data set imported with what its manifest states, as `softwrist import` would.
void import_dataset(const fs::path& data, const fs::path& real, const std::map<std::string, fs::path>& rigs) {
  const std::string source = (data / "manifest.json").string();
  const nlohmann::json manifest = io::parse_json(io::read_text_file(data / "manifest.json"), source);
  io::JsonReader top(manifest, source, "");
  const nlohmann::json& files = top.raw("files");
  if (!files.is_array()) top.fail("files", "must be a list");
  for (std::size_t i = 0; i < files.size(); ++i) {
    io::JsonReader entry(files[i], source, fmt::format("files[{}]", i));
    const std::string csv = entry.text("csv"), rig = entry.text("rig");
    const auto placement = rigs.find(rig);
    if (placement == rigs.end()) entry.fail("rig", fmt::format("no placement file for rig '{}'", rig));
    diagnosis::ImportOptions options{.kind = entry.text("kind"),
                                     .posture = entry.text("posture", ""),
                                     .torque_includes = entry.text("torque_includes", ""),
                                     .angles_zeroed = entry.boolean("angles_zeroed_at_start", false),
                                     .angle_resolution_deg = entry.non_negative("angle_resolution_deg", 0.0),
                                     .placement = fs::absolute(placement->second).string(),
                                     .muscle = entry.text("muscle", "flexor")};
    diagnosis::import_csv(data / csv, real / fs::path(csv).stem(), options);
  }
}

// Which of a pair is larger: each form alone at its level, with the case's seed, measured by the generator's truth.
std::vector<std::string> larger_first(const IndependentCase& c, const std::vector<double>& levels,
                                      const IndependentBenchOptions& options, const fs::path& dir) {
  std::vector<std::pair<double, std::string>> sized;
  for (std::size_t i = 0; i < c.forms.size(); ++i) {
    const fs::path alone = dir / fmt::format("alone_{}", i);
    const independent::DatasetTruth truth = independent::write_dataset(
        {.seed = c.seed, .effects = {{c.forms[i], levels[i]}}, .trajectory_s = options.trajectory_s}, alone);
    fs::remove_all(alone);
    sized.emplace_back(truth.magnitude_noise_units, expected_label(c.forms[i]));
  }
  std::stable_sort(sized.begin(), sized.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::string> labels;
  for (const auto& [size, label] : sized) labels.push_back(label);
  return labels;
}

IndependentRun run_case(const IndependentCase& c, const IndependentBenchOptions& options,
                        const sim::DeviceDescription& nominal) {
  const auto start = std::chrono::steady_clock::now();
  IndependentRun run{.case_name = c.name(), .category = category_of(c), .seed = c.seed, .index = c.index};
  run.forms = c.forms;
  run.levels = draw_levels(c, options.min_level);
  const fs::path dir = options.scratch / fmt::format("{}-{}", c.name(), c.seed);
  fs::remove_all(dir);
  try {
    if (run.category == CaseCategory::kPair) {
      const std::vector<std::string> labels = larger_first(c, run.levels, options, dir);
      run.expected = labels[0];
      run.expected_second = labels[1];
    } else {
      run.expected = c.forms.empty() ? "none" : expected_label(c.forms[0]);
    }
    const independent::DatasetTruth truth = independent::write_dataset(
        {.seed = c.seed, .effects = effect_specs(c.forms, run.levels), .trajectory_s = options.trajectory_s},
        dir / "data");
    run.magnitude_noise_units = truth.magnitude_noise_units;
    import_dataset(dir / "data", dir / "real", options.rigs);
    diagnosis::ReplayEngine engine(sim::PluginSet::Default());
    // Diagnosed with the grid's largest explained_fraction, so that each setting's decision is exact (redecide()),
    // then decided with the run's own settings and on the grid.
    diagnosis::DiagnosisOptions diagnosed_with = options.diagnosis;
    for (const DecisionSettings& g : decision_grid())
      diagnosed_with.explained_fraction = std::max(diagnosed_with.explained_fraction, g.explained_fraction);
    diagnosis::Diagnosis d =
        diagnosis::diagnose(diagnosis::load_real_data(dir / "real"), nominal, engine, diagnosed_with);
    for (const DecisionSettings& g : decision_grid()) {
      diagnosis::Diagnosis decided = d;
      diagnosis::redecide(decided, with_settings(options.diagnosis, g));
      run.by_setting.push_back({.settings = g, .verdict = decided.verdict, .also_effects = decided.also_effects});
    }
    diagnosis::redecide(d, options.diagnosis);
    run.verdict = d.verdict;
    run.leading_effect = d.leading_effect;
    run.also_effects = d.also_effects;
    run.explained_fraction = d.explained_fraction;
    run.gap_closed = d.gap_closed();
    if (options.keep) std::ofstream(dir / "diagnosis.json") << diagnosis::to_json(d).dump(2) << "\n";
  } catch (const std::exception& e) {
    run.error = e.what();
  }
  if (!options.keep) fs::remove_all(dir);
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

nlohmann::json rate_json(int right, int cases) {
  const auto [low, high] = wilson_interval(right, cases);
  return {{"rate", cases > 0 ? nlohmann::json(static_cast<double>(right) / cases) : nlohmann::json(nullptr)},
          {"ci95", {low, high}},
          {"right", right},
          {"cases", cases}};
}

// The detection curve's magnitude bands, in noise units.
constexpr double kBandEdges[] = {0.0, 1.0, 2.0, 4.0, 8.0, 16.0, 1e300};

nlohmann::json detection_curve(const std::vector<IndependentRun>& runs) {
  nlohmann::json curve = nlohmann::json::array();
  for (std::size_t b = 0; b + 1 < std::size(kBandEdges); ++b) {
    int right = 0, cases = 0;
    for (const auto& r : runs) {
      if (r.category != CaseCategory::kSingle || !r.error.empty()) continue;
      if (r.magnitude_noise_units < kBandEdges[b] || r.magnitude_noise_units >= kBandEdges[b + 1]) continue;
      ++cases;
      right += r.correct() ? 1 : 0;
    }
    nlohmann::json band = rate_json(right, cases);
    band["from_noise_units"] = kBandEdges[b];
    band["to_noise_units"] =
        b + 2 < std::size(kBandEdges) ? nlohmann::json(kBandEdges[b + 1]) : nlohmann::json(nullptr);
    curve.push_back(band);
  }
  return curve;
}

nlohmann::json settings_json(const DecisionSettings& g) {
  return {{"explained_fraction", g.explained_fraction},
          {"pair_share", g.pair_share},
          {"contradiction_gap", g.contradiction_gap}};
}

nlohmann::json run_json(const IndependentRun& r) {
  nlohmann::json by_setting = nlohmann::json::array();
  for (const SettingVerdict& v : r.by_setting) {
    nlohmann::json entry = settings_json(v.settings);
    entry["verdict"] = v.verdict;
    entry["also_effects"] = v.also_effects;
    by_setting.push_back(entry);
  }
  return {{"case", r.case_name},
          {"category", category_name(r.category)},
          {"seed", r.seed},
          {"index", r.index},
          {"forms", r.forms},
          {"levels", r.levels},
          {"expected", r.expected},
          {"expected_second", r.expected_second},
          {"verdict", r.verdict},
          {"leading_effect", r.leading_effect},
          {"also_effects", r.also_effects},
          {"explained_fraction", r.explained_fraction},
          {"gap_closed", r.gap_closed},
          {"magnitude_noise_units", r.magnitude_noise_units},
          {"wall_s", r.wall_s},
          {"error", r.error},
          {"by_setting", by_setting}};
}

std::vector<SettingVerdict> settings_verdicts_from_json(const nlohmann::json& list, const std::string& source,
                                                        std::size_t run) {
  std::vector<SettingVerdict> verdicts;
  for (std::size_t k = 0; k < list.size(); ++k) {
    io::JsonReader e(list[k], source, fmt::format("runs[{}].by_setting[{}]", run, k));
    SettingVerdict v{.settings = {.explained_fraction = e.number("explained_fraction"),
                                  .pair_share = e.number("pair_share"),
                                  .contradiction_gap = e.number("contradiction_gap")},
                     .verdict = e.text("verdict")};
    try {
      v.also_effects = e.raw("also_effects").get<std::vector<std::string>>();
    } catch (const nlohmann::json::exception&) {
      e.fail("also_effects", "must be a list of names");
    }
    e.finish();
    verdicts.push_back(std::move(v));
  }
  return verdicts;
}

bool same_settings(const DecisionSettings& a, const DecisionSettings& b) {
  return a.explained_fraction == b.explained_fraction && a.pair_share == b.pair_share &&
         a.contradiction_gap == b.contradiction_gap;
}

// How far a setting lies from another, in steps of 0.1, 0.1 and 0.5 noise units (the ties' rule).
double settings_distance(const DecisionSettings& a, const DecisionSettings& b) {
  return std::abs(a.explained_fraction - b.explained_fraction) / 0.1 + std::abs(a.pair_share - b.pair_share) / 0.1 +
         std::abs(a.contradiction_gap - b.contradiction_gap) / 0.5;
}

}  // namespace

DecisionSettings decision_settings(const diagnosis::DiagnosisOptions& options) {
  return {.explained_fraction = options.explained_fraction,
          .pair_share = options.pair_share,
          .contradiction_gap = options.contradiction_gap};
}

diagnosis::DiagnosisOptions with_settings(diagnosis::DiagnosisOptions options, const DecisionSettings& settings) {
  options.explained_fraction = settings.explained_fraction;
  options.pair_share = settings.pair_share;
  options.contradiction_gap = settings.contradiction_gap;
  return options;
}

// 0.3 since the as-placed leader's share is counted beyond the whole tolerance fit (b0dcb20), which lowers the shares
// that name an effect; seed 1001's first calibration tied 0.4 and 0.5, the grid's lower edge then.
std::vector<DecisionSettings> decision_grid() {
  std::vector<DecisionSettings> grid;
  for (double explained : {0.3, 0.4, 0.5, 0.6, 0.7}) {
    for (double pair : {0.2, 0.3, 0.4}) {
      for (double contradiction : {1.5, 2.0, 3.0}) grid.push_back({explained, pair, contradiction});
    }
  }
  return grid;
}

nlohmann::json calibrate_decisions(const std::vector<IndependentRun>& runs, const DecisionSettings& current) {
  const std::vector<DecisionSettings> grid = decision_grid();
  std::set<std::uint64_t> seeds;
  for (const IndependentRun& r : runs) {
    seeds.insert(r.seed);
    if (!r.error.empty()) continue;
    bool same = r.by_setting.size() == grid.size();
    for (std::size_t k = 0; same && k < grid.size(); ++k) same = same_settings(r.by_setting[k].settings, grid[k]);
    if (!same)
      throw std::invalid_argument(fmt::format(
          "{} (seed {}) was not decided on this build's grid of settings (a run from before the grid existed?)",
          r.case_name, r.seed));
  }
  nlohmann::json settings = nlohmann::json::array();
  std::size_t best = 0;
  double best_objective = -1.0;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    std::vector<IndependentRun> decided = runs;
    for (IndependentRun& r : decided) {
      if (!r.error.empty()) continue;
      r.verdict = r.by_setting[k].verdict;
      r.also_effects = r.by_setting[k].also_effects;
    }
    const nlohmann::json counts = summarize(decided)["counts"];
    nlohmann::json entry = settings_json(grid[k]);
    double sum = 0.0;
    int categories = 0;
    for (const char* category : {"single", "none", "outside", "pairs"}) {
      entry[category] = counts[category]["rate"];
      if (counts[category]["cases"] == 0) continue;
      sum += counts[category]["rate"].get<double>();
      ++categories;
    }
    const double objective = categories > 0 ? sum / categories : 0.0;
    entry["objective"] = objective;
    settings.push_back(entry);
    const bool better = objective > best_objective + 1e-12;
    const bool tie = std::abs(objective - best_objective) <= 1e-12;
    if (better || (tie && settings_distance(grid[k], current) < settings_distance(grid[best], current))) {
      best = k;
      best_objective = objective;
    }
  }
  nlohmann::json record;
  record["seeds"] = seeds;
  record["cases"] = runs.size();
  record["objective"] =
      "mean of the rates of the single catalogue forms named, none on the nominal device, unexplained on the outside "
      "forms and the pairs' larger effect named (a category without cases left out); ties to the nearest to current";
  record["settings"] = settings;
  record["chosen"] = settings[best];
  record["current"] = settings_json(current);
  return record;
}

void redecide_runs(std::vector<IndependentRun>& runs, const DecisionSettings& settings) {
  for (IndependentRun& r : runs) {
    if (!r.error.empty()) continue;
    const auto it = std::find_if(r.by_setting.begin(), r.by_setting.end(),
                                 [&](const SettingVerdict& v) { return same_settings(v.settings, settings); });
    if (it == r.by_setting.end())
      throw std::invalid_argument(fmt::format(
          "{} (seed {}) holds no verdict for explained_fraction {:g}, pair_share {:g}, contradiction_gap {:g}",
          r.case_name, r.seed, settings.explained_fraction, settings.pair_share, settings.contradiction_gap));
    r.verdict = it->verdict;
    r.also_effects = it->also_effects;
  }
}

std::string IndependentCase::name() const {
  if (forms.empty()) return "none";
  std::string name = forms[0];
  for (std::size_t i = 1; i < forms.size(); ++i) name += "+" + forms[i];
  return name;
}

std::vector<std::pair<std::string, std::string>> IndependentBenchOptions::default_pairs() {
  return {{"aged_fabric", "exponential_limits"},
          {"strap_linear_preload", "slow_vent"},
          {"elliptical_section", "dahl_friction"},
          {"forearm_imu_roll", "tondu_end_effect"},
          {"glove_slide", "second_order_response"}};
}

std::vector<IndependentCase> independent_cases(const IndependentBenchOptions& options) {
  if (options.seeds < 1) throw std::invalid_argument("the benchmark needs at least one seed per case");
  if (options.shard_count < 1 || options.shard_index < 1 || options.shard_index > options.shard_count)
    throw std::invalid_argument("the shard must be K/N with 1 <= K <= N");
  std::vector<std::vector<std::string>> kinds;
  if (options.nominal) kinds.push_back({});
  if (options.forms.empty()) {
    for (const auto& f : independent::effect_forms()) {
      if (f.label != "none") kinds.push_back({f.name});
    }
  } else {
    for (const auto& f : options.forms) {
      if (f != "none") kinds.push_back({f});  // the nominal is its own case (options.nominal)
    }
  }
  for (const auto& [a, b] : options.pairs) {
    if (expected_label(a) == expected_label(b))
      throw std::invalid_argument(fmt::format("the pair {}+{} has one label twice", a, b));
    kinds.push_back({a, b});
  }
  for (const auto& forms : kinds) {
    for (const auto& f : forms) form_info(f);  // an unknown form is refused before anything runs
  }
  std::vector<IndependentCase> cases;
  int index = 0;
  for (int s = 0; s < options.seeds; ++s) {
    for (const auto& forms : kinds) {
      if (index % options.shard_count == options.shard_index - 1)
        cases.push_back({.forms = forms, .seed = options.first_seed + static_cast<std::uint64_t>(s), .index = index});
      ++index;
    }
  }
  return cases;
}

std::vector<IndependentRun> run_independent_benchmark(const IndependentBenchOptions& options) {
  const std::vector<IndependentCase> cases = independent_cases(options);
  if (!options.rigs.contains("prototype"))
    throw std::invalid_argument("the benchmark needs the prototype's placement file (rig 'prototype')");
  const sim::DeviceDescription nominal = sim::load_device(options.rigs.at("prototype"));
  std::vector<IndependentRun> runs(cases.size());
  parallel_for(static_cast<int>(cases.size()), options.jobs, [&](int k) {
    runs[static_cast<std::size_t>(k)] = run_case(cases[static_cast<std::size_t>(k)], options, nominal);
  });
  return runs;
}

nlohmann::json summarize(const std::vector<IndependentRun>& unsorted) {
  std::vector<IndependentRun> runs = unsorted;
  // Keyed by seed and index: the runs of several reported seeds merge into one record (a calibration over them).
  const auto key = [](const IndependentRun& r) { return std::pair{r.seed, r.index}; };
  std::sort(runs.begin(), runs.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
  for (std::size_t i = 1; i < runs.size(); ++i) {
    if (key(runs[i]) == key(runs[i - 1]))
      throw std::invalid_argument(fmt::format("case {} ({}, seed {}) appears twice: the same shard merged twice?",
                                              runs[i].index, runs[i].case_name, runs[i].seed));
  }
  const auto count = [&](CaseCategory category, auto&& right) {
    int k = 0, n = 0;
    for (const auto& r : runs) {
      if (r.category != category || !r.error.empty()) continue;
      ++n;
      k += right(r) ? 1 : 0;
    }
    return std::pair{k, n};
  };
  const auto correct = [](const IndependentRun& r) { return r.correct(); };
  const auto [top1, singles] = count(CaseCategory::kSingle, correct);
  const auto [none, nominal] = count(CaseCategory::kNone, correct);
  const auto [unexplained, outside] = count(CaseCategory::kOutside, correct);
  const auto [primary, pairs] = count(CaseCategory::kPair, correct);
  const int second = count(CaseCategory::kPair, [](const IndependentRun& r) {
                       return r.correct() && std::find(r.also_effects.begin(), r.also_effects.end(),
                                                       r.expected_second) != r.also_effects.end();
                     }).first;
  double closed = 0.0;
  for (const auto& r : runs) closed += r.category == CaseCategory::kSingle && r.error.empty() ? r.gap_closed : 0.0;

  const nlohmann::json single = rate_json(top1, singles), nominal_case = rate_json(none, nominal),
                       outside_forms = rate_json(unexplained, outside), pair = rate_json(primary, pairs);
  nlohmann::json j;
  j["generator"] = "independent";
  j["top1_accuracy"] = single["rate"];
  j["top1_ci95"] = single["ci95"];
  j["none_correct_rate"] = nominal_case["rate"];
  j["none_correct_rate_ci95"] = nominal_case["ci95"];
  j["unexplained_correct_rate"] = outside_forms["rate"];
  j["unexplained_correct_rate_ci95"] = outside_forms["ci95"];
  j["pairs_primary_correct_rate"] = pair["rate"];
  j["pairs_primary_correct_rate_ci95"] = pair["ci95"];
  j["pairs_second_reported_rate"] = rate_json(second, pairs)["rate"];
  j["mean_shrink_fraction"] = singles > 0 ? nlohmann::json(closed / singles) : nlohmann::json();
  j["counts"] = {{"single", single},
                 {"none", nominal_case},
                 {"outside", outside_forms},
                 {"pairs", pair},
                 {"errors", std::count_if(runs.begin(), runs.end(), [](const auto& r) { return !r.error.empty(); })}};
  j["targets"] = {{"top1_accuracy", kTop1Target},
                  {"top1_ci95_low", kTop1LowerBoundTarget},
                  {"none_correct_rate", kNoneTarget},
                  {"unexplained_correct_rate", kUnexplainedTarget},
                  {"pairs_primary_correct_rate", kPairsTarget},
                  {"mean_shrink_fraction", kGapClosedTarget}};
  j["detection_curve"] = detection_curve(runs);
  std::map<std::string, std::map<std::string, int>> confusion;  // expected -> verdict -> count
  for (const auto& r : runs) ++confusion[r.expected][r.error.empty() ? r.verdict : "error"];
  j["confusion"] = confusion;
  j["runs"] = nlohmann::json::array();
  for (const auto& r : runs) j["runs"].push_back(run_json(r));
  return j;
}

std::vector<IndependentRun> runs_from_json(const nlohmann::json& summary, const std::string& source) {
  io::JsonReader top(summary, source, "");
  const nlohmann::json& list = top.raw("runs");
  if (!list.is_array()) top.fail("runs", "must be a list");
  std::vector<IndependentRun> runs;
  for (std::size_t i = 0; i < list.size(); ++i) {
    io::JsonReader r(list[i], source, fmt::format("runs[{}]", i));
    IndependentRun run{.case_name = r.text("case"),
                       .seed = static_cast<std::uint64_t>(r.integer("seed")),
                       .index = static_cast<int>(r.integer("index")),
                       .expected = r.text("expected"),
                       .expected_second = r.text("expected_second", ""),
                       .verdict = r.text("verdict"),
                       .leading_effect = r.text("leading_effect", ""),
                       .explained_fraction = r.number("explained_fraction"),
                       .gap_closed = r.number("gap_closed"),
                       .magnitude_noise_units = r.number("magnitude_noise_units"),
                       .wall_s = r.number("wall_s"),
                       .error = r.text("error", "")};
    const std::string category = r.text("category");
    bool known = false;
    for (CaseCategory c : {CaseCategory::kNone, CaseCategory::kSingle, CaseCategory::kOutside, CaseCategory::kPair}) {
      if (category == category_name(c)) run.category = c, known = true;
    }
    if (!known) r.fail("category", fmt::format("unknown category '{}'", category));
    const auto list_of = [&](const std::string& key, auto& into) {
      try {
        into = r.raw(key).get<std::remove_reference_t<decltype(into)>>();
      } catch (const nlohmann::json::exception&) {
        r.fail(key, "must be a list of the right type");
      }
    };
    list_of("forms", run.forms);
    list_of("levels", run.levels);
    list_of("also_effects", run.also_effects);
    if (r.has("by_setting")) {
      const nlohmann::json& grid = r.raw("by_setting");
      if (!grid.is_array()) r.fail("by_setting", "must be a list");
      run.by_setting = settings_verdicts_from_json(grid, source, i);
    }
    r.finish();
    runs.push_back(std::move(run));
  }
  return runs;
}

}  // namespace softwrist::diagnosis_bench
