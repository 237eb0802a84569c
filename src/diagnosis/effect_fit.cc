#include "diagnosis/effect_fit.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <optional>
#include <span>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "optimize/bounded_search.h"

namespace softwrist::diagnosis {
namespace {

std::vector<double> values_of(const EffectSpec& spec, std::span<const double> u) {
  std::vector<double> v(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) v[i] = spec.parameters[i].from_unit(u[i]);
  return v;
}

// The coarse start grid in the unit cube (the search is local): one parameter, five levels; two or three, the
// corners and centre of the 3^n grid (sum of indices even); four or more, the centre and each parameter at 0.2 and
// 0.8 with the others central (2n + 1 points: the even 3^n grid has 41 at n = 4, each a replay of every trial). In
// the order they are tried.
std::vector<std::vector<double>> start_grid(std::size_t n) {
  if (n >= 4) {
    std::vector<std::vector<double>> grid{std::vector<double>(n, 0.5)};
    for (std::size_t i = 0; i < n; ++i) {
      for (const double level : {0.2, 0.8}) {
        grid.push_back(std::vector<double>(n, 0.5));
        grid.back()[i] = level;
      }
    }
    return grid;
  }
  const std::vector<double> levels =
      n == 1 ? std::vector<double>{0.05, 0.25, 0.5, 0.75, 0.95} : std::vector<double>{0.2, 0.5, 0.8};
  std::vector<std::vector<double>> grid;
  std::vector<std::size_t> index(n, 0);
  for (bool more = true; more;) {
    std::vector<double> u(n);
    for (std::size_t i = 0; i < n; ++i) u[i] = levels[index[i]];
    std::size_t index_sum = 0;
    for (std::size_t i = 0; i < n; ++i) index_sum += index[i];
    if (n == 1 || index_sum % 2 == 0) grid.push_back(std::move(u));
    more = false;
    for (std::size_t i = 0; i < n && !more; ++i) {
      if (++index[i] < levels.size())
        more = true;
      else
        index[i] = 0;
    }
  }
  return grid;
}

struct SearchedPoint {
  std::vector<double> u;  // in the unit cube
  double training_error = 0.0;
};

// The fit's search: the start (the effect's own starting values), the grid, then BOBYQA from the best of them.
SearchedPoint search_unit_cube(const std::function<double(std::span<const double>)>& objective,
                               std::vector<double> start_u, int max_evaluations) {
  const std::size_t n = start_u.size();
  SearchedPoint best{.u = std::move(start_u), .training_error = 0.0};
  best.training_error = objective(best.u);
  for (const std::vector<double>& u : start_grid(n)) {
    const double value = objective(u);
    if (value < best.training_error) best = {.u = u, .training_error = value};
  }
  const optimize::BoundedSearchResult found =
      optimize::minimize_bounded(objective, best.u,
                                 {.algorithm = optimize::LocalAlgorithm::kBobyqa,
                                  .lower = std::vector<double>(n, 0.0),
                                  .upper = std::vector<double>(n, 1.0),
                                  .initial_step = std::vector<double>(n, 0.08),
                                  .x_tolerance_abs = 1e-4,
                                  .f_tolerance_rel = 1e-7,
                                  .max_evaluations = max_evaluations});
  if (found.value <= best.training_error) best = {.u = found.x, .training_error = found.value};
  return best;
}

// The predictions with `variant`, a trial the effect does not act on keeping the base model's.
Predictions predictions_with(const GapProblem& problem, const ModelVariant& variant, const EffectSpec& spec,
                             bool training_only, const Predictions& base) {
  Predictions predictions = problem.evaluate(variant, training_only, &spec);
  for (std::size_t t = 0; t < problem.size(); ++t) {
    if (predictions[t].empty()) predictions[t] = base[t];
  }
  return predictions;
}

}  // namespace

std::vector<EffectId> requested_effects(const DiagnosisOptions& options) {
  std::vector<EffectId> ids = options.effects;
  if (ids.empty()) {
    for (const auto& spec : effect_catalogue()) ids.push_back(spec.id);
  }
  return ids;
}

std::vector<bool> gap_trials_acted_on(const std::vector<TrialGap>& trials, const EffectSpec& spec) {
  std::vector<bool> acted_on;
  for (const TrialGap& t : trials) acted_on.push_back(t.gap && spec.acts_on_kind(t.kind));
  return acted_on;
}

EffectFit fit_effect(const GapProblem& problem, EffectId id, const BaseModel& base,
                     const sim::DeviceDescription& nominal, const DiagnosisOptions& options, std::uint64_t seed) {
  const EffectSpec& spec = effect_spec(id);
  EffectFit fit{.id = id, .name = spec.name};
  fit.applicable = std::any_of(problem.trials().begin(), problem.trials().end(),
                               [&](const PreparedTrial& t) { return spec.acts_on_kind(t.trial->kind); });
  fit.train_error_before = problem.training_error(base.training);
  const UnitSums before = problem.heldout_sums(base.full);
  fit.heldout_error_before = problem.heldout_error(before);
  if (!fit.applicable) {
    fit.heldout_error_after = fit.heldout_error_before;
    fit.train_error_after = fit.train_error_before;
    return fit;
  }
  const auto variant_at = [&](std::span<const double> values) {
    ModelVariant v = base.variant;
    apply_effect(id, values, v);
    return v;
  };
  const auto objective = [&](std::span<const double> u) {
    ++fit.evaluations;
    try {
      const double error = problem.training_error(
          predictions_with(problem, variant_at(values_of(spec, u)), spec, /*training_only=*/true, base.training));
      return std::isfinite(error) ? error : kInfeasible;
    } catch (const std::exception&) {  // an unphysical device (physics::InvalidParameter) or a diverged replay
      return kInfeasible;
    }
  };
  const std::vector<double> start = fit_start(id, base.variant.device);
  std::vector<double> start_u(start.size());
  for (std::size_t i = 0; i < start.size(); ++i) start_u[i] = spec.parameters[i].to_unit(start[i]);
  // BOBYQA's model of n parameters needs 2n + 1 points before its first step: a larger effect gets a larger budget.
  const int budget = options.max_evaluations + 15 * std::max(0, static_cast<int>(start_u.size()) - 2);
  const SearchedPoint searched = search_unit_cube(objective, std::move(start_u), budget);
  fit.values = values_of(spec, searched.u);
  fit.params = describe_values(id, fit.values, nominal);
  fit.train_error_after = searched.training_error;

  // Held out: the full replay with the fitted effect.
  const UnitSums after =
      problem.heldout_sums(predictions_with(problem, variant_at(fit.values), spec, /*training_only=*/false, base.full));
  fit.heldout_error_after = problem.heldout_error(after);
  fit.shrink_fraction = fraction_closed(fit.heldout_error_before, fit.heldout_error_after);
  std::tie(fit.ci_low, fit.ci_high) = bootstrap_interval(problem, before, after, options.bootstrap, seed);
  fit.heldout_after_sums = after;
  return fit;
}

std::size_t leader_of_round(const GapProblem& problem, std::vector<EffectFit>& fits, const DiagnosisOptions& options,
                            std::uint64_t seed, const std::function<bool(const EffectFit&)>& eligible) {
  const auto competes = [&](const EffectFit& f) { return f.applicable && (!eligible || eligible(f)); };
  std::size_t best = fits.size();
  for (std::size_t k = 0; k < fits.size(); ++k) {
    if (competes(fits[k]) && (best == fits.size() || fits[k].heldout_error_after < fits[best].heldout_error_after))
      best = k;
  }
  if (best == fits.size()) return best;
  std::size_t leader = best;
  for (std::size_t k = 0; k < fits.size(); ++k) {
    EffectFit& f = fits[k];
    if (!competes(f)) continue;
    f.se_of_difference_to_best = k == best
                                     ? 0.0
                                     : paired_difference_se(problem, f.heldout_after_sums,
                                                            fits[best].heldout_after_sums, options.bootstrap, seed);
    f.within_one_se_of_best = f.heldout_error_after <= fits[best].heldout_error_after + f.se_of_difference_to_best;
    if (!options.one_se_rule || !f.within_one_se_of_best) continue;
    const EffectFit& l = fits[leader];
    if (f.values.size() < l.values.size() ||
        (f.values.size() == l.values.size() && f.heldout_error_after < l.heldout_error_after))
      leader = k;
  }
  return leader;
}

}  // namespace softwrist::diagnosis
