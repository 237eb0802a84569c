#pragma once
// The withheld-effect benchmark on data softwrist did not generate (issue 20): data sets from the independent device
// (src/independent_device: its own fPAM law, geometry, dynamics, regulators and coloured, quantised sensors), each
// file imported with what its manifest states, as a user would (the rig, posture, what a sweep's torque includes,
// zeroed angles, the sensor's resolution), diagnosed against the independent device's own nominal rigs
// (experiments/independent_device/) without the label, and scored against truth.json.
//
// Cases: the nominal device (truth `none`), every effect form alone (a catalogue label, or `outside:` for forms the
// catalogue does not have: the verdict should be `unexplained`), and pairs of forms of two labels (the verdict should
// name the larger, measured as the larger single-effect magnitude in truth.json, and report the other). Each seed
// draws the device's variation, the conventions, the noise and, per effect, a level log-uniform in [min_level, 1],
// so that magnitudes run from well above the noise down to near it (the detection curve).
//
// Runs are independent of how they are sharded: case k of the full list runs in shard (k mod N) + 1 of N, each
// with its own seeds, and the summary is computed from the runs alone, so merged shards give the same figures.

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "diagnosis/diagnosis.h"

namespace softwrist::diagnosis_bench {

// What a case is judged as.
enum class CaseCategory { kNone, kSingle, kOutside, kPair };

struct IndependentCase {
  std::vector<std::string> forms;  // empty: the nominal device
  std::uint64_t seed = 0;
  int index = 0;             // its position in the full list (shards and merges keep this order)
  std::string name() const;  // "none", "aged_fabric", "aged_fabric+slow_vent"
};

struct IndependentBenchOptions {
  std::vector<std::string> forms;  // single forms ("none" adds nothing); empty: every form of effect_forms()
  std::vector<std::pair<std::string, std::string>> pairs = default_pairs();
  bool nominal = true;  // the nominal device's case
  int seeds = 20;
  std::uint64_t first_seed = 1;
  double trajectory_s = 12.0;
  double min_level = 0.2;  // each effect's level log-uniform in [min_level, 1]
  int shard_index = 1, shard_count = 1;
  int jobs = 2;  // data sets diagnosed in parallel, each diagnosis on one thread
  std::filesystem::path scratch;
  bool keep = false;  // keep each data set, its imported logs and diagnosis.json under scratch
  // The placement file of each rig a manifest names (torque_rig, prototype).
  std::map<std::string, std::filesystem::path> rigs;
  diagnosis::DiagnosisOptions diagnosis{.jobs = 1, .bootstrap = 100};

  // Pairs of forms of different labels, each catalogue label in at least one, and one with an outside effect.
  static std::vector<std::pair<std::string, std::string>> default_pairs();
};

// The verdict's decision settings (DiagnosisOptions: explained_fraction, pair_share, contradiction_gap), calibrated
// on seeds apart from the reported ones (experiments/diagnosis_calibration/).
struct DecisionSettings {
  double explained_fraction = 0.0, pair_share = 0.0, contradiction_gap = 0.0;
};
// The decision settings `options` holds, and `options` with `settings` in their place.
DecisionSettings decision_settings(const diagnosis::DiagnosisOptions& options);
diagnosis::DiagnosisOptions with_settings(diagnosis::DiagnosisOptions options, const DecisionSettings& settings);
// The grid each run is decided on besides its own settings: every combination of explained_fraction 0.3-0.7,
// pair_share 0.2-0.4 and contradiction_gap 1.5-3 noise units (experiments/diagnosis_calibration/README.md).
std::vector<DecisionSettings> decision_grid();

struct SettingVerdict {
  DecisionSettings settings;
  std::string verdict;
  std::vector<std::string> also_effects;
};

struct IndependentRun {
  std::string case_name;
  CaseCategory category{};
  std::uint64_t seed = 0;
  int index = 0;
  std::vector<std::string> forms;
  std::vector<double> levels;
  std::string expected;         // the label the verdict should be
  std::string expected_second;  // pairs: the smaller effect's label, to be reported beside it
  std::string verdict, leading_effect;
  std::vector<std::string> also_effects;
  double explained_fraction = 0.0, gap_closed = 0.0;
  double magnitude_noise_units = 0.0;  // truth.json: the largest effect over the noise in any file
  double wall_s = 0.0;
  std::string error;  // set when the case could not be run; such a case is counted apart, never as right
  std::vector<SettingVerdict> by_setting;  // the same diagnosis decided on each of decision_grid()

  bool correct() const { return error.empty() && verdict == expected; }
};

// The cases of the full list (every seed), then those of one shard.
std::vector<IndependentCase> independent_cases(const IndependentBenchOptions& options);

// Runs the shard's cases. Throws std::invalid_argument for an unknown form or a rig without a placement file.
std::vector<IndependentRun> run_independent_benchmark(const IndependentBenchOptions& options);

// Every figure, computed from the runs alone (so from merged shards too): the rates with their Wilson 95 %
// intervals and counts (top1 over single catalogue forms, none, unexplained over outside forms, the pairs' larger
// effect named and the second reported), the mean gap closed, the confusion per label, the detection curve (the
// single forms' top-1 rate per magnitude band, in noise units) and the runs themselves.
nlohmann::json summarize(const std::vector<IndependentRun>& runs);

// A summary's runs read back (softwrist diagnose-bench --merge): errors name the file and the field.
std::vector<IndependentRun> runs_from_json(const nlohmann::json& summary, const std::string& source);

// The decision settings chosen from calibration runs (seeds apart from the reported ones): each setting of the runs'
// grid scored as summarize() scores the runs, by the mean of its four rates (top-1, none, unexplained over outside
// forms, the pairs' larger effect named; a category without cases left out); the best chosen, ties going to the
// setting nearest `current` (distances summed in steps of 0.1, 0.1 and 0.5 noise units). Returns the record
// experiments/diagnosis_calibration/ keeps: {"seeds", "cases", "objective", "settings": [...], "chosen", "current"}.
// Throws std::invalid_argument for runs without a grid (from before it existed) or with differing grids.
nlohmann::json calibrate_decisions(const std::vector<IndependentRun>& runs, const DecisionSettings& current);

// Each run's verdict (and also_effects) replaced by the one its grid holds for `settings`: what a build deciding with
// them says of runs diagnosed by another (the fits do not depend on these settings). Throws std::invalid_argument
// naming a run whose grid does not hold them.
void redecide_runs(std::vector<IndependentRun>& runs, const DecisionSettings& settings);

// The targets on the independent generator.
inline constexpr double kTop1Target = 0.9, kTop1LowerBoundTarget = 0.8, kNoneTarget = 0.9, kUnexplainedTarget = 0.8,
                        kPairsTarget = 0.8, kGapClosedTarget = 0.7;

}  // namespace softwrist::diagnosis_bench
