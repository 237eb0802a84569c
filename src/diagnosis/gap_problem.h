#pragma once
// The diagnosis's data as an estimation problem (diagnosis.h): the prepared trials, their predictions under a model
// variant, and the errors the fits minimise (training part) and the verdict weighs (held-out part), in units of each
// trial's noise and averaged over the trials of each kind, then over the kinds. Internal to src/diagnosis.

#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "diagnosis/effects.h"
#include "diagnosis/replay.h"
#include "diagnosis/unit_sums.h"

namespace softwrist::diagnosis {

// A failed replay or an unphysical parameter makes the objective this large, so the search turns away.
inline constexpr double kInfeasible = 1e12;

// The sum of squares of weighted training residuals (GapProblem::training_residuals: the training error), or
// kInfeasible where there are none (the model could not be built or replayed).
inline double sum_of_squares_or_infeasible(const std::optional<std::vector<double>>& residuals) {
  if (!residuals) return kInfeasible;
  double sum = 0.0;
  for (const double v : *residuals) sum += v * v;
  return sum;
}

using Predictions = std::vector<std::vector<double>>;  // [trial][point]

class GapProblem {
 public:
  GapProblem(std::vector<PreparedTrial>& trials, ReplayEngine& engine) : trials_(trials), engine_(engine) {}

  // The variant's predictions; with `only_changed`, a trial the effect does not act on is left empty (the caller
  // fills in the base model's). kCoarse only for a Jacobian's differences (Fidelity).
  Predictions evaluate(const ModelVariant& variant, bool training_only, const EffectSpec* only_changed = nullptr,
                       Fidelity fidelity = Fidelity::kFine) const;

  // The fit's objective: mean over kinds of the mean over trials of mean (r/sigma)^2 over training measurements.
  double training_error(const Predictions& predictions) const;
  // The same as residuals, each weighted so that their sum of squares is training_error (for least squares).
  std::vector<double> training_residuals(const Predictions& predictions) const;
  UnitSums heldout_sums(const Predictions& predictions) const;
  // The same sums over the training measurements (of predictions on all the data).
  UnitSums training_sums(const Predictions& predictions) const;
  // The held-out error of unit sums, with each unit counted `weights[t][u]` times (1 for the data as it is); with
  // `only`, over the trials it marks; otherwise over the scored trials (set_scored), all by default.
  double heldout_error(const UnitSums& sums, const std::vector<std::vector<int>>* weights = nullptr,
                       const std::vector<bool>* only = nullptr) const;
  // The training part's systematic residual, as heldout_error measures the held-out part but over every trial (the
  // fits minimise the training error over every trial, and a model that leaves a trial the tolerances explain as it
  // was has not accounted for it): of training_sums, each unit counted `weights[t][u]` times.
  double training_gap(const UnitSums& sums, const std::vector<std::vector<int>>* weights = nullptr) const;
  // Units with held-out (training) measurements, per trial, for the bootstrap.
  std::vector<std::vector<std::size_t>> heldout_units() const { return units_of(true); }
  std::vector<std::vector<std::size_t>> training_units() const { return units_of(false); }

  // The trials the held-out error is taken over from now on (the verdict: those with a gap beyond the tolerances).
  void set_scored(std::vector<bool> scored) { scored_ = std::move(scored); }
  bool scored(std::size_t trial) const { return scored_.empty() || scored_[trial]; }

  std::size_t size() const { return trials_.size(); }
  // Whether some trial's replay depends on the simulation's step (ReplayEngine::depends_on_step): only then do coarse
  // replays cost less than fine ones.
  bool depends_on_step() const;
  const std::vector<PreparedTrial>& trials() const { return trials_; }
  ReplayEngine& engine() const { return engine_; }

 private:
  UnitSums sums_of(const Predictions& predictions, bool heldout) const;
  std::vector<std::vector<std::size_t>> units_of(bool heldout) const;
  double systematic_error(const UnitSums& sums, const std::vector<std::vector<int>>* weights,
                          const std::vector<bool>* only) const;
  double mean_over_kinds(const std::vector<bool>* only, const std::function<double(std::size_t)>& per_trial) const;

  std::vector<PreparedTrial>& trials_;
  ReplayEngine& engine_;
  std::vector<bool> scored_;  // empty: every trial
};

// The fraction of a held-out error `before` that `after` closes: (before - after) / before, 0 when there was none.
inline double fraction_closed(double before, double after) { return before > 0.0 ? (before - after) / before : 0.0; }

// The bootstrap's 95 % interval of the shrink fraction, resampling each trial's held-out units with replacement;
// both models see the same resample. Resamples with no gap left to shrink are left out.
std::pair<double, double> bootstrap_interval(const GapProblem& problem, const UnitSums& before, const UnitSums& after,
                                             int resamples, std::uint64_t seed);
// The bootstrap standard error of heldout_error(a) - heldout_error(b), both taken on the same resamples of the
// held-out units (paired): how far apart two models' held-out errors must lie before these data tell them apart.
double paired_difference_se(const GapProblem& problem, const UnitSums& a, const UnitSums& b, int resamples,
                            std::uint64_t seed);
// The same of training_gap(a) - training_gap(b), resampling the training units of every trial.
double paired_training_difference_se(const GapProblem& problem, const UnitSums& a, const UnitSums& b, int resamples,
                                     std::uint64_t seed);

}  // namespace softwrist::diagnosis
