#pragma once
// The withheld-effect benchmark of the gap diagnosis: "real" data from a simulated exosuit (synthetic_device.h) with
// one effect injected at a random plausible magnitude, or none, or one outside the catalogue, handed to diagnose()
// without its label and scored: the confusion matrix, top-1 attribution, the held-out gap closed, and the false
// attributions of the no-effect and outside-catalogue cases.
//
// What keeps it honest:
//  - every case's device also differs from the nominal by small device-to-device variations (fPAM, wrist radius,
//    relaxed wrist, regulator, mounts), so the nominal model is never exactly right;
//  - the injected effects are written in synthetic_device.cc, not through the catalogue's code, and most in another
//    functional form than the one the catalogue fits (make_bench_case says which);
//  - the magnitudes are drawn per seed from ranges fixed before the benchmark was run, stronger or weaker than the
//    nominal where an effect has both directions.

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "diagnosis/diagnosis.h"
#include "diagnosis/synthetic_device.h"
#include "sim/device.h"

namespace softwrist::diagnosis {

inline constexpr const char* kNoEffect = "none";
// Outside the catalogue: the muscles rub where they cross the wrist (dry friction along each tendon path).
inline constexpr const char* kOutsideEffect = "wrap_friction";

// The catalogue's effects, then "none", then the outside effect.
std::vector<std::string> bench_case_names();

struct BenchCase {
  std::string injected;  // a catalogue effect, kNoEffect or kOutsideEffect
  std::uint64_t seed = 0;
  SyntheticDevice real;
  std::string magnitude;  // what was injected, in words and numbers
};

// The real device of one case: `nominal` with device-to-device variations (scaled by `variation`, 1 the assumed
// tolerances of benchmark.cc) and the injected effect drawn from `seed`.
BenchCase make_bench_case(const std::string& injected, std::uint64_t seed, const sim::DeviceDescription& nominal,
                          double variation = 1.0);

struct BenchOptions {
  int seeds = 5;  // per case
  std::uint64_t first_seed = 1;
  int jobs = 2;                    // data sets diagnosed in parallel (each diagnosis on one thread)
  std::vector<std::string> cases;  // all of bench_case_names() when empty
  SyntheticPlan plan{.repetitions = 2, .trajectory_s = 24.0};
  DiagnosisOptions diagnosis{.jobs = 1, .bootstrap = 100};
  std::filesystem::path scratch;  // data sets are synthesized under it and removed
  bool keep = false;              // keep each data set under scratch, with its diagnosis.json (no plots)
  bool paper_case = true;         // also run the paper's case (stretching withheld) once
  double variation = 1.0;         // scale of the device-to-device variations
};

struct BenchRun {
  std::string injected, magnitude, verdict;
  std::uint64_t seed = 0;
  double heldout_before = 0.0, heldout_after = 0.0;  // the diagnosis's held-out error, nominal and corrected
  double shrink_fraction = 0.0;  // the held-out gap closed: Diagnosis::gap_closed() (over the trials with a gap)
  double wall_s = 0.0;
};

struct PaperCaseResult {
  std::string verdict;
  double torque_mae_before_nm = 0.0, torque_mae_after_nm = 0.0;  // the torque sweep, nominal and corrected model
  double k_series_n_per_cm2 = 0.0;
};

struct BenchResult {
  std::vector<BenchRun> runs;
  std::map<std::string, std::map<std::string, int>> confusion;  // injected -> verdict -> count
  double top1_accuracy = 0.0;                                   // single catalogue effects named first
  double mean_shrink_fraction = 0.0;                            // over the single catalogue effects
  double none_correct_rate = 0.0;                               // "none" on the no-effect case
  double unexplained_correct_rate = 0.0;                        // "unexplained" on the outside case
  std::optional<PaperCaseResult> paper_case;
  double wall_s = 0.0;
};

// The targets.
inline constexpr double kTop1Target = 0.9, kShrinkTarget = 0.7, kNoneTarget = 0.8, kUnexplainedTarget = 0.8;

BenchResult run_benchmark(const sim::DeviceDescription& nominal, const BenchOptions& options);

// The torque sweeps' mean absolute error [N m] of the nominal (or, with `corrected`, the corrected) model.
double torque_mae(const Diagnosis& d, bool corrected);

nlohmann::json to_json(const BenchResult& result);

}  // namespace softwrist::diagnosis
