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

#include "optimize/bounded_least_squares.h"

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

// A fit's training residuals over the unit cube, from fine replays (every value compared) and from coarse ones (a
// Jacobian's differences only: Fidelity).
struct Residuals {
  optimize::ResidualFunction fine, coarse;
};

// The polish's budget: n + 2 replays per Levenberg-Marquardt iteration (a Jacobian on coarse replays with its base
// point, a step on fine ones), so a larger effect gets a larger one, 15 evaluations per parameter beyond two.
int search_budget(int max_evaluations, std::size_t parameters) {
  return max_evaluations + 15 * std::max(0, static_cast<int>(parameters) - 2);
}

// The indices of `spec`'s extensions (ParameterSpec::extension), or of its base form's parameters.
std::vector<std::size_t> parameter_indices(const EffectSpec& spec, bool extensions) {
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
    if (spec.parameters[i].extension == extensions) indices.push_back(i);
  }
  return indices;
}

// The parameters `fit` moved, as the one-standard-error rule counts them: its base form's, and its extensions where
// they were kept (EffectFit::extended). An extension held at its neutral value is no freedom the fit used; counted, an
// effect lost ties for slots it never fitted (the mounts' three extensions made their one stiffness four).
std::size_t fitted_parameters(const EffectFit& fit) {
  const EffectSpec& spec = effect_spec(fit.id);
  return fit.extended ? spec.parameters.size() : parameter_indices(spec, /*extensions=*/false).size();
}

// Levenberg-Marquardt on the training residuals from `from` within the unit cube. The training error is a sum of
// squares, and its Gauss-Newton model follows the valleys where one parameter trades against another (the fPAM's
// fabric against its r0): BOBYQA, which models the error as a quadratic from 2n + 1 samples, spent its whole budget of
// 80 replays in that valley and stopped at a training error 2.5 times the one this reaches in 31.
SearchedPoint polish(const Residuals& residuals, const SearchedPoint& from, int max_evaluations) {
  if (!(from.training_error < kInfeasible)) return from;  // nowhere feasible to start from
  const std::size_t n = from.u.size();
  const optimize::LeastSquaresResult found =
      optimize::minimize_least_squares(residuals.fine, from.u,
                                       {.lower = std::vector<double>(n, 0.0),
                                        .upper = std::vector<double>(n, 1.0),
                                        .max_evaluations = max_evaluations,
                                        .jobs = 1,  // the effects are fitted in parallel already
                                        .difference_residuals = residuals.coarse});
  if (!(found.cost <= from.training_error)) return from;
  return {.u = found.x, .training_error = found.cost};
}

// The best of `candidates` (the first of equals): ranked on coarse replays, and the first of that ranking evaluated on
// fine ones (Fidelity), with every candidate whose coarse replay failed (a step too coarse for a stiff corner). The
// candidates are a start grid or the extensions at 0.2, 0.5 and 0.8 of their ranges, mostly further apart than the
// coarse step moves a training error; a coarse replay costs a quarter of a fine one. Every candidate is evaluated fine
// where there are no coarse residuals or none of those evaluated fine is feasible.
SearchedPoint best_of(const Residuals& residuals, const std::vector<std::vector<double>>& candidates) {
  std::vector<bool> fine(candidates.size(), !residuals.coarse);
  if (residuals.coarse) {
    std::size_t first = candidates.size();
    double first_coarse = kInfeasible;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const double value = sum_of_squares_or_infeasible(residuals.coarse(candidates[i]));
      if (value < first_coarse) std::tie(first, first_coarse) = std::pair(i, value);
      fine[i] = !(value < kInfeasible);
    }
    if (first < candidates.size()) fine[first] = true;
  }
  SearchedPoint best{.u = candidates.front(), .training_error = kInfeasible};
  for (const bool all : {false, true}) {
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (fine[i] == all) continue;  // the first pass: those marked; the second: the others
      const double value = sum_of_squares_or_infeasible(residuals.fine(candidates[i]));
      if (value < best.training_error) best = {.u = candidates[i], .training_error = value};
    }
    if (best.training_error < kInfeasible) break;
  }
  return best;
}

// The start and the grid over its joined coordinates (start_grid), the separable ones (ParameterSpec::separable) held
// at their start; each of those crossed with every separable coordinate also at the middle of its range.
std::vector<std::vector<double>> start_candidates(const std::vector<double>& start_u,
                                                  const std::vector<bool>& separable) {
  std::vector<std::size_t> joined;
  for (std::size_t i = 0; i < start_u.size(); ++i) {
    if (!separable[i]) joined.push_back(i);
  }
  std::vector<std::vector<double>> candidates{start_u};
  for (const std::vector<double>& g : start_grid(joined.size())) {
    candidates.push_back(start_u);
    for (std::size_t k = 0; k < joined.size(); ++k) candidates.back()[joined[k]] = g[k];
  }
  for (std::size_t i = 0; i < start_u.size(); ++i) {
    if (!separable[i] || start_u[i] == 0.5) continue;
    const std::size_t n = candidates.size();
    for (std::size_t c = 0; c < n; ++c) {
      candidates.push_back(candidates[c]);
      candidates.back()[i] = 0.5;
    }
  }
  return candidates;
}

// The fit's search: the best of the start (the effect's own starting values) and the grid, then the polish from it.
SearchedPoint search_unit_cube(const Residuals& residuals, const std::vector<double>& start_u,
                               const std::vector<bool>& separable, int max_evaluations) {
  return polish(residuals, best_of(residuals, start_candidates(start_u, separable)), max_evaluations);
}

// The base form's search (fit_effect): its parameters (those not ParameterSpec::extension) from the start, the grid
// and the polish, the others held at their starting values.
SearchedPoint search_base_form(const Residuals& residuals, const std::vector<double>& start_u, const EffectSpec& spec,
                               int max_evaluations) {
  const std::vector<std::size_t> base_indices = parameter_indices(spec, /*extensions=*/false);
  const auto expand = [&](std::span<const double> reduced) {
    std::vector<double> u = start_u;
    for (std::size_t k = 0; k < reduced.size(); ++k) u[base_indices[k]] = reduced[k];
    return u;
  };
  std::vector<double> reduced_start;
  std::vector<bool> separable;
  for (const std::size_t i : base_indices) {
    reduced_start.push_back(start_u[i]);
    separable.push_back(spec.parameters[i].separable);
  }
  Residuals reduced{.fine = [&](std::span<const double> r) { return residuals.fine(expand(r)); }, .coarse = {}};
  if (residuals.coarse) reduced.coarse = [&](std::span<const double> r) { return residuals.coarse(expand(r)); };
  SearchedPoint found =
      search_unit_cube(reduced, reduced_start, separable, search_budget(max_evaluations, base_indices.size()));
  found.u = expand(found.u);
  return found;
}

// The extensions' search (extend_fit): the extensions over their own start grid (start_grid) from the base form's
// optimum, from the effect's start, and from the start with each base parameter in turn at 0.2 and at 0.8 of its
// range; then the polish over every parameter from the best of them (as best_of ranks them) and of the base optimum.
// A base form that has taken part of an extension's effect can sit far from the joint optimum, and an extension can
// need its base form elsewhere than either: a wrist surface longer along the forearm is wrapped only with a smaller
// radius across it, and with the nominal's radius it holds the hand mount (an infeasible start; seed 18's
// elliptical_section: training error 226 at the base optimum, 19.5 at the generator's ellipse).
SearchedPoint search_extensions(const Residuals& residuals, const SearchedPoint& base_optimum,
                                const std::vector<double>& start_u, const EffectSpec& spec, int max_evaluations) {
  std::vector<std::vector<double>> origins{base_optimum.u, start_u};
  for (const std::size_t i : parameter_indices(spec, /*extensions=*/false)) {
    for (const double level : {0.2, 0.8}) {
      origins.push_back(start_u);
      origins.back()[i] = level;
    }
  }
  const std::vector<std::size_t> extension_indices = parameter_indices(spec, /*extensions=*/true);
  const std::vector<std::vector<double>> grid = start_grid(extension_indices.size());
  std::vector<std::vector<double>> candidates;
  for (const std::vector<double>& origin : origins) {
    for (const std::vector<double>& g : grid) {
      candidates.push_back(origin);
      for (std::size_t k = 0; k < extension_indices.size(); ++k) candidates.back()[extension_indices[k]] = g[k];
    }
  }
  SearchedPoint best = best_of(residuals, candidates);
  if (!(best.training_error < base_optimum.training_error)) best = base_optimum;
  return polish(residuals, best, max_evaluations);
}

// The predictions with `variant`, a trial the effect does not act on keeping the base model's.
Predictions predictions_with(const GapProblem& problem, const ModelVariant& variant, const EffectSpec& spec,
                             bool training_only, const Predictions& base, Fidelity fidelity = Fidelity::kFine) {
  Predictions predictions = problem.evaluate(variant, training_only, &spec, fidelity);
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

std::vector<bool> gap_trials_acted_on(const GapProblem& problem, const std::vector<TrialGap>& trials,
                                      const EffectSpec& spec, bool as_placed) {
  std::vector<bool> acted_on;
  for (std::size_t t = 0; t < trials.size(); ++t)
    acted_on.push_back((as_placed ? trials[t].gap_as_placed : trials[t].gap) && acts_on(spec, problem.trials()[t]));
  return acted_on;
}

namespace {

// One effect on one base model: the fit's residuals over the unit cube (the weighted training residuals, counting
// evaluations into `evaluations`), the held-out sums at a point and the base model's, and the effect's start.
struct EffectObjective {
  EffectObjective(const GapProblem& gap_problem, EffectId id, const BaseModel& base_model, int& evaluation_count)
      : problem(gap_problem),
        spec(effect_spec(id)),
        base(base_model),
        evaluations(evaluation_count),
        before(gap_problem.heldout_sums(base_model.full)) {
    const std::vector<double> start = fit_start(id, base.variant.device);
    for (std::size_t i = 0; i < start.size(); ++i) start_u.push_back(spec.parameters[i].to_unit(start[i]));
  }
  ModelVariant variant_at(std::span<const double> u) const {
    ModelVariant v = base.variant;
    apply_effect(spec.id, values_of(spec, u), v);
    return v;
  }
  std::optional<std::vector<double>> residuals(std::span<const double> u, Fidelity fidelity) const {
    ++evaluations;
    try {
      std::vector<double> r = problem.training_residuals(
          predictions_with(problem, variant_at(u), spec, /*training_only=*/true, base.training, fidelity));
      if (!std::all_of(r.begin(), r.end(), [](double v) { return std::isfinite(v); })) return std::nullopt;
      return r;
    } catch (const std::exception&) {  // an unphysical device (physics::InvalidParameter) or a diverged replay
      return std::nullopt;
    }
  }
  // No coarse residuals where every trial the effect changes replays alike at either step (regulator_lag where
  // measured pressures drive the angles): they would only repeat the fine ones.
  Residuals residual_functions() const {
    Residuals r{.fine = [this](std::span<const double> u) { return residuals(u, Fidelity::kFine); }, .coarse = {}};
    if (std::any_of(problem.trials().begin(), problem.trials().end(),
                    [&](const PreparedTrial& t) { return acts_on(spec, t) && problem.engine().depends_on_step(t); }))
      r.coarse = [this](std::span<const double> u) { return residuals(u, Fidelity::kCoarse); };
    return r;
  }
  // The held-out sums at `u`, and the training sums into `training` where given.
  UnitSums heldout_at(std::span<const double> u, UnitSums* training = nullptr) const {
    const Predictions full = predictions_with(problem, variant_at(u), spec, /*training_only=*/false, base.full);
    if (training != nullptr) *training = problem.training_sums(full);
    return problem.heldout_sums(full);
  }

  const GapProblem& problem;
  const EffectSpec& spec;
  const BaseModel& base;
  int& evaluations;
  UnitSums before;  // the base model's held-out sums
  std::vector<double> start_u;
};

// `fit`'s values, training error, held-out error and its interval, at the unit-cube point `at`.
void record(EffectFit& fit, const EffectObjective& objective, const SearchedPoint& at, const UnitSums& after,
            const UnitSums& training_after, const sim::DeviceDescription& nominal, const DiagnosisOptions& options,
            std::uint64_t seed) {
  fit.values = values_of(objective.spec, at.u);
  fit.params = describe_values(fit.id, fit.values, nominal);
  fit.train_error_after = at.training_error;
  fit.heldout_error_after = objective.problem.heldout_error(after);
  // Where it acts, until measure_shares_where_acting (diagnosis.cc) reads the trials: the same.
  fit.shrink_fraction = fit.shrink_where_acting = fraction_closed(fit.heldout_error_before, fit.heldout_error_after);
  std::tie(fit.ci_low, fit.ci_high) =
      bootstrap_interval(objective.problem, objective.before, after, options.bootstrap, seed);
  fit.heldout_after_sums = after;
  fit.training_after_sums = training_after;
  fit.training_gap_after = objective.problem.training_gap(training_after);
}

}  // namespace

EffectSearch search_effect(const GapProblem& problem, EffectId id, const BaseModel& base,
                           const DiagnosisOptions& options) {
  const EffectSpec& spec = effect_spec(id);
  EffectSearch s;
  s.applicable = std::any_of(problem.trials().begin(), problem.trials().end(),
                             [&](const PreparedTrial& t) { return acts_on(spec, t); });
  if (!s.applicable) return s;
  // The base form: the extensions (ParameterSpec::extension) held at their starting values, the neutral or the
  // nominal's own (extend_fit tries them).
  const EffectObjective objective(problem, id, base, s.evaluations);
  const SearchedPoint searched =
      search_base_form(objective.residual_functions(), objective.start_u, spec, options.max_evaluations);
  s.u = searched.u;
  s.training_error = searched.training_error;
  s.heldout_after = objective.heldout_at(searched.u, &s.training_after);
  return s;
}

EffectFit fit_effect(const GapProblem& problem, EffectId id, const BaseModel& base,
                     const sim::DeviceDescription& nominal, const DiagnosisOptions& options, std::uint64_t seed,
                     const EffectSearch* searched) {
  const EffectSpec& spec = effect_spec(id);
  EffectFit fit{.id = id, .name = spec.name};
  const EffectSearch search = searched != nullptr ? *searched : search_effect(problem, id, base, options);
  fit.applicable = search.applicable;
  fit.evaluations = search.evaluations;
  fit.train_error_before = problem.training_error(base.training);
  int recorded = 0;  // record() replays nothing
  const EffectObjective objective(problem, id, base, recorded);
  fit.heldout_error_before = problem.heldout_error(objective.before);
  if (!fit.applicable) {
    fit.heldout_error_after = fit.heldout_error_before;
    fit.train_error_after = fit.train_error_before;
    return fit;
  }
  record(fit, objective, {.u = search.u, .training_error = search.training_error}, search.heldout_after,
         search.training_after, nominal, options, seed);
  return fit;
}

bool extend_fit(const GapProblem& problem, EffectFit& fit, const BaseModel& base, const sim::DeviceDescription& nominal,
                const DiagnosisOptions& options, std::uint64_t seed) {
  const EffectSpec& spec = effect_spec(fit.id);
  if (!fit.applicable || parameter_indices(spec, /*extensions=*/true).empty()) return false;
  const EffectObjective objective(problem, fit.id, base, fit.evaluations);
  SearchedPoint base_optimum{.u = {}, .training_error = fit.train_error_after};
  for (std::size_t i = 0; i < spec.parameters.size(); ++i)
    base_optimum.u.push_back(spec.parameters[i].to_unit(fit.values[i]));
  const SearchedPoint extended =
      search_extensions(objective.residual_functions(), base_optimum, objective.start_u, spec,
                        search_budget(options.max_evaluations, spec.parameters.size()));
  if (!(extended.training_error < base_optimum.training_error)) return false;
  UnitSums training_after;
  const UnitSums after = objective.heldout_at(extended.u, &training_after);
  const double se = paired_difference_se(problem, fit.heldout_after_sums, after, options.bootstrap, seed);
  if (!(problem.heldout_error(after) < fit.heldout_error_after - se)) return false;
  fit.base_form = EffectFit::BaseForm{.params = fit.params,
                                      .shrink_fraction = fit.shrink_fraction,
                                      .shrink_where_acting = fit.shrink_where_acting,
                                      .heldout_after_sums = fit.heldout_after_sums};
  record(fit, objective, extended, after, training_after, nominal, options, seed);
  fit.extended = true;
  return true;
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
  std::size_t best_trained = best;  // of those within one standard error, the lowest training gap
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
    const std::size_t fp = fitted_parameters(f) + f.base_parameters, lp = fitted_parameters(l) + l.base_parameters;
    if (fp < lp || (fp == lp && f.heldout_error_after < l.heldout_error_after)) leader = k;
    if (f.training_gap_after < fits[best_trained].training_gap_after) best_trained = k;
  }
  if (leader == best_trained || !(options.training_separation_se > 0.0)) return leader;
  const double se = paired_training_difference_se(problem, fits[leader].training_after_sums,
                                                  fits[best_trained].training_after_sums, options.bootstrap, seed);
  const double margin = fits[leader].training_gap_after - fits[best_trained].training_gap_after;
  return margin > options.training_separation_se * se ? best_trained : leader;
}

bool joins_combination(const EffectFit& fit, bool interval_informative, const DiagnosisOptions& options) {
  return fit.applicable && fit.shrink_fraction >= options.min_gain && (fit.ci_low > 0.0 || !interval_informative);
}

std::size_t leader_of_single_fits(const GapProblem& problem, std::vector<EffectFit>& fits,
                                  const DiagnosisOptions& options, std::uint64_t seed, bool interval_informative) {
  // Each fit's standard error and whether it is within one, against the lowest error of all (as reported); then the
  // leader among those that may join, whose call measures them against its own best and is undone.
  const std::size_t overall = leader_of_round(problem, fits, options, seed);
  std::vector<std::pair<double, bool>> recorded;
  for (const EffectFit& f : fits) recorded.emplace_back(f.se_of_difference_to_best, f.within_one_se_of_best);
  const std::size_t joining = leader_of_round(problem, fits, options, seed, [&](const EffectFit& f) {
    return joins_combination(f, interval_informative, options);
  });
  for (std::size_t k = 0; k < fits.size(); ++k)
    std::tie(fits[k].se_of_difference_to_best, fits[k].within_one_se_of_best) = recorded[k];
  return joining < fits.size() ? joining : overall;
}

}  // namespace softwrist::diagnosis
