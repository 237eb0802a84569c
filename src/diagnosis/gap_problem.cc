#include "diagnosis/gap_problem.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "diagnosis/setting_scatter.h"

namespace softwrist::diagnosis {

Predictions GapProblem::evaluate(const ModelVariant& variant, bool training_only, const EffectSpec* only_changed,
                                 Fidelity fidelity) const {
  Predictions predictions(trials_.size());
  for (std::size_t t = 0; t < trials_.size(); ++t) {
    // A trial the effect does not act on keeps the base model's predictions (filled by the caller).
    if (only_changed != nullptr && !acts_on(*only_changed, trials_[t])) continue;
    predictions[t] = engine_.predict(trials_[t], variant, training_only, fidelity);
  }
  return predictions;
}

bool GapProblem::depends_on_step() const {
  return std::any_of(trials_.begin(), trials_.end(),
                     [&](const PreparedTrial& t) { return engine_.depends_on_step(t); });
}

double GapProblem::training_error(const Predictions& predictions) const {
  return mean_over_kinds(nullptr, [&](std::size_t t) {
    const PreparedTrial& trial = trials_[t];
    const std::vector<double> r = whitened(trial, residuals_of(trial, predictions[t]), SplitPart::kTraining);
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < trial.points.size(); ++i) {
      if (trial.points[i].heldout) continue;
      sum += std::pow(r[i] / trial.noise, 2);
      ++n;
    }
    return n > 0 ? sum / n : 0.0;
  });
}

std::vector<double> GapProblem::training_residuals(const Predictions& predictions) const {
  // training_error = (1 / kinds) sum over kinds of (1 / trials of the kind) sum over its trials of the mean square.
  std::map<TrialKind, int> trials_of_kind;
  for (const PreparedTrial& trial : trials_) ++trials_of_kind[trial.trial->kind];
  std::vector<double> residuals;
  for (std::size_t t = 0; t < trials_.size(); ++t) {
    const PreparedTrial& trial = trials_[t];
    const auto n = std::count_if(trial.points.begin(), trial.points.end(), [](const Point& p) { return !p.heldout; });
    if (n == 0) continue;
    const double weight = std::sqrt(1.0 / (static_cast<double>(trials_of_kind.size()) *
                                           trials_of_kind[trial.trial->kind] * static_cast<double>(n))) /
                          trial.noise;
    const std::vector<double> r = whitened(trial, residuals_of(trial, predictions[t]), SplitPart::kTraining);
    for (std::size_t i = 0; i < trial.points.size(); ++i) {
      if (!trial.points[i].heldout) residuals.push_back(weight * r[i]);
    }
  }
  return residuals;
}

UnitSums GapProblem::sums_of(const Predictions& predictions, bool heldout) const {
  UnitSums sums;
  for (std::size_t t = 0; t < trials_.size(); ++t) {
    const PreparedTrial& trial = trials_[t];
    int units = 0;
    for (const auto& p : trial.points) units = std::max(units, p.unit + 1);
    std::vector<std::pair<double, int>> per_unit(static_cast<std::size_t>(units));
    const std::vector<double> r =
        whitened(trial, residuals_of(trial, predictions[t]), heldout ? SplitPart::kHeldOut : SplitPart::kTraining);
    for (std::size_t i = 0; i < trial.points.size(); ++i) {
      if (trial.points[i].heldout != heldout) continue;
      auto& u = per_unit[static_cast<std::size_t>(trial.points[i].unit)];
      u.first += std::pow(r[i] / trial.noise, 2);
      ++u.second;
    }
    sums.per_trial.push_back(std::move(per_unit));
  }
  return sums;
}

UnitSums GapProblem::heldout_sums(const Predictions& predictions) const { return sums_of(predictions, true); }

UnitSums GapProblem::training_sums(const Predictions& predictions) const { return sums_of(predictions, false); }

double GapProblem::heldout_error(const UnitSums& sums, const std::vector<std::vector<int>>* weights,
                                 const std::vector<bool>* only) const {
  return systematic_error(sums, weights, only != nullptr || scored_.empty() ? only : &scored_);
}

double GapProblem::training_gap(const UnitSums& sums, const std::vector<std::vector<int>>* weights) const {
  return systematic_error(sums, weights, nullptr);
}

double GapProblem::systematic_error(const UnitSums& sums, const std::vector<std::vector<int>>* weights,
                                    const std::vector<bool>* only) const {
  return mean_over_kinds(only, [&](std::size_t t) {
    double sum = 0.0;
    double n = 0.0;
    for (std::size_t u = 0; u < sums.per_trial[t].size(); ++u) {
      const double w = weights ? (*weights)[t][u] : 1.0;
      sum += w * sums.per_trial[t][u].first;
      n += w * sums.per_trial[t][u].second;
    }
    return n > 0 ? std::sqrt(std::max(0.0, sum / n - 1.0)) : 0.0;
  });
}

std::vector<std::vector<std::size_t>> GapProblem::units_of(bool heldout) const {
  std::vector<std::vector<std::size_t>> units(trials_.size());
  for (std::size_t t = 0; t < trials_.size(); ++t) {
    std::set<std::size_t> seen;
    for (const auto& p : trials_[t].points) {
      if (p.heldout == heldout) seen.insert(static_cast<std::size_t>(p.unit));
    }
    units[t].assign(seen.begin(), seen.end());
  }
  return units;
}

double GapProblem::mean_over_kinds(const std::vector<bool>* only,
                                   const std::function<double(std::size_t)>& per_trial) const {
  std::map<TrialKind, std::pair<double, int>> by_kind;
  for (std::size_t t = 0; t < trials_.size(); ++t) {
    if (only != nullptr && !(*only)[t]) continue;
    auto& k = by_kind[trials_[t].trial->kind];
    k.first += per_trial(t);
    ++k.second;
  }
  double total = 0.0;
  for (const auto& [kind, k] : by_kind) total += k.first / k.second;
  return by_kind.empty() ? 0.0 : total / static_cast<double>(by_kind.size());
}

namespace {

// Calls `each(weights)` for `resamples` resamples of each trial's `units` with replacement (weights[t][u]: how often
// unit u of trial t was drawn), the same sequence for the same seed.
void for_each_resample(const GapProblem& problem, const std::vector<std::vector<std::size_t>>& units, int resamples,
                       std::uint64_t seed, const UnitSums& shape,
                       const std::function<void(const std::vector<std::vector<int>>&)>& each) {
  std::mt19937_64 rng(seed);
  std::vector<std::vector<int>> weights(problem.size());
  for (int b = 0; b < resamples; ++b) {
    for (std::size_t t = 0; t < problem.size(); ++t) {
      weights[t].assign(shape.per_trial[t].size(), 0);
      if (units[t].empty()) continue;
      std::uniform_int_distribution<std::size_t> pick(0, units[t].size() - 1);
      for (std::size_t k = 0; k < units[t].size(); ++k) ++weights[t][units[t][pick(rng)]];
    }
    each(weights);
  }
}

}  // namespace

std::pair<double, double> bootstrap_interval(const GapProblem& problem, const UnitSums& before, const UnitSums& after,
                                             int resamples, std::uint64_t seed) {
  // The scored held-out units the change moves at all. A change that acts on some units only (a wrap on the angles
  // where the muscle wraps, a lag on the trials whose pressures move) leaves the rest bit for bit; a resample drawn
  // from those alone closes exactly 0, and with few units per trial (a torque sweep holds out four angles of a
  // muscle) such resamples fill the lower 2.5 % whatever the moved units say.
  std::vector<std::vector<bool>> moved(before.per_trial.size());
  int units_moved = 0;
  for (std::size_t t = 0; t < before.per_trial.size(); ++t) {
    for (std::size_t u = 0; u < before.per_trial[t].size(); ++u) {
      const double a = before.per_trial[t][u].first, b = after.per_trial[t][u].first;
      moved[t].push_back(problem.scored(t) && std::abs(a - b) > 1e-12 * std::max(std::abs(a), std::abs(b)));
      units_moved += moved[t].back() ? 1 : 0;
    }
  }
  // Conditioned only where at least two units move: given that a single moved unit is drawn, every resample would
  // hold it, and a change that fits one held angle would have an interval above zero on that one alone.
  const bool conditioned = units_moved >= 2;
  std::vector<double> shrinks;
  for_each_resample(
      problem, problem.heldout_units(), resamples, seed, before, [&](const std::vector<std::vector<int>>& weights) {
        bool holds_a_moved_unit = !conditioned;
        for (std::size_t t = 0; t < weights.size() && !holds_a_moved_unit; ++t) {
          for (std::size_t u = 0; u < weights[t].size() && !holds_a_moved_unit; ++u)
            holds_a_moved_unit = weights[t][u] > 0 && moved[t][u];
        }
        const double e0 = problem.heldout_error(before, &weights), e1 = problem.heldout_error(after, &weights);
        // A resample without any gap (all its units where the model was already right), or without any unit the change
        // moves, says nothing of the shrink: the interval is the shrink's given that the resample holds something to
        // shrink.
        if (e0 > 0.0 && holds_a_moved_unit) shrinks.push_back((e0 - e1) / e0);
      });
  if (shrinks.empty()) return {0.0, 0.0};
  std::sort(shrinks.begin(), shrinks.end());
  const auto at = [&](double q) {
    return shrinks[static_cast<std::size_t>(q * static_cast<double>(shrinks.size() - 1))];
  };
  return {at(0.025), at(0.975)};
}

namespace {

// The bootstrap standard error of error(a) - error(b) over paired resamples of `units`.
double paired_se(const GapProblem& problem, const std::vector<std::vector<std::size_t>>& units, const UnitSums& a,
                 const UnitSums& b, int resamples, std::uint64_t seed,
                 const std::function<double(const UnitSums&, const std::vector<std::vector<int>>&)>& error) {
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for_each_resample(problem, units, resamples, seed, a, [&](const std::vector<std::vector<int>>& weights) {
    const double d = error(a, weights) - error(b, weights);
    sum += d;
    sum2 += d * d;
    ++n;
  });
  if (n < 2) return 0.0;
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, (sum2 - n * mean * mean) / (n - 1)));
}

}  // namespace

double paired_difference_se(const GapProblem& problem, const UnitSums& a, const UnitSums& b, int resamples,
                            std::uint64_t seed) {
  return paired_se(
      problem, problem.heldout_units(), a, b, resamples, seed,
      [&](const UnitSums& s, const std::vector<std::vector<int>>& w) { return problem.heldout_error(s, &w); });
}

double paired_training_difference_se(const GapProblem& problem, const UnitSums& a, const UnitSums& b, int resamples,
                                     std::uint64_t seed) {
  return paired_se(
      problem, problem.training_units(), a, b, resamples, seed,
      [&](const UnitSums& s, const std::vector<std::vector<int>>& w) { return problem.training_gap(s, &w); });
}

}  // namespace softwrist::diagnosis
