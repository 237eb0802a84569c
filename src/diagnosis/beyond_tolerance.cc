#include "diagnosis/beyond_tolerance.h"

#include <algorithm>
#include <tuple>

#include "common/parallel_for.h"
#include "diagnosis/effect_fit.h"
#include "diagnosis/tolerance_fit.h"

namespace softwrist::diagnosis {
namespace {

using BeyondTolerance = Diagnosis::BeyondTolerance;

// The share of the held-out gap beyond the tolerances above which the leader, fitted on them as they were fitted, is
// not refitted jointly with them.
constexpr double kSettled = 0.9;

// The tolerance fit's model and its errors: what every effect is measured against.
struct Within {
  Predictions full;
  UnitSums sums;
  double train_error = 0.0;
};

Within within_of(const GapProblem& problem, const ToleranceFit& within) {
  Within w{.full = problem.evaluate(*within.variant, false)};
  w.sums = problem.heldout_sums(w.full);
  w.train_error = problem.training_error(problem.evaluate(*within.variant, true));
  return w;
}

double fraction_closed(double before, double after) { return before > 0.0 ? (before - after) / before : 0.0; }

// b's errors and fractions with its model (b.variant) against the tolerance fit's.
void score(const GapProblem& problem, const Within& w, const std::vector<TrialGap>& trials,
           const DiagnosisOptions& options, std::uint64_t seed, BeyondTolerance& b) {
  b.train_error_within = w.train_error;
  b.train_error_with_effect = problem.training_error(problem.evaluate(*b.variant, true));
  const UnitSums after = problem.heldout_sums(problem.evaluate(*b.variant, false));
  b.heldout_error_within = problem.heldout_error(w.sums);
  b.heldout_error_with_effect = problem.heldout_error(after);
  b.explained_fraction = fraction_closed(b.heldout_error_within, b.heldout_error_with_effect);
  const EffectSpec& spec = effect_spec(b.id);
  std::vector<bool> acted_on;
  for (const TrialGap& t : trials) acted_on.push_back(t.gap && spec.acts_on_kind(t.kind));
  if (std::any_of(acted_on.begin(), acted_on.end(), [](bool a) { return a; })) {
    b.explained_in_acted_on = fraction_closed(problem.heldout_error(w.sums, nullptr, &acted_on),
                                              problem.heldout_error(after, nullptr, &acted_on));
  }
  std::tie(b.ci_low, b.ci_high) = bootstrap_interval(problem, w.sums, after, options.bootstrap, seed);
}

// Effect `id` fitted on `base` (its own parameters searched as fit_effect does; the base held).
BeyondTolerance fit_on(const GapProblem& problem, EffectId id, const ModelVariant& base,
                       const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options,
                       std::uint64_t seed) {
  const Predictions training = problem.evaluate(base, true), full = problem.evaluate(base, false);
  const EffectFit fit = fit_effect(problem, id, {.variant = base, .training = training, .full = full}, nominal_device,
                                   options, seed);
  BeyondTolerance b{.id = id, .effect = fit.name, .values = fit.values, .params = fit.params};
  b.evaluations = fit.evaluations + 2;
  b.variant.emplace(base);
  apply_effect(id, fit.values, *b.variant);
  return b;
}

std::vector<EffectId> applicable_effects(const GapProblem& problem, const DiagnosisOptions& options) {
  std::vector<EffectId> ids = options.effects;
  if (ids.empty()) {
    for (const auto& spec : effect_catalogue()) ids.push_back(spec.id);
  }
  std::erase_if(ids, [&](EffectId id) {
    const EffectSpec& spec = effect_spec(id);
    return std::none_of(problem.trials().begin(), problem.trials().end(),
                        [&](const PreparedTrial& t) { return spec.acts_on_kind(t.trial->kind); });
  });
  return ids;
}

void sort_by_training_error(std::vector<BeyondTolerance>& ranked) {
  std::stable_sort(ranked.begin(), ranked.end(), [](const BeyondTolerance& a, const BeyondTolerance& b) {
    return a.train_error_with_effect < b.train_error_with_effect;
  });
}

}  // namespace

std::vector<BeyondTolerance> rank_beyond_tolerances(const GapProblem& problem, const ModelVariant& nominal,
                                                    const sim::DeviceDescription& nominal_device,
                                                    const ToleranceFit& within, const std::vector<TrialGap>& trials,
                                                    const DiagnosisOptions& options) {
  if (within.params.empty() || !within.variant) return {};
  const Within w = within_of(problem, within);
  const std::vector<EffectId> ids = applicable_effects(problem, options);
  std::vector<BeyondTolerance> ranked(ids.size());
  parallel_for(static_cast<int>(ids.size()), options.jobs, [&](int k) {
    const EffectId id = ids[static_cast<std::size_t>(k)];
    const std::uint64_t seed = options.seed + 2000 + static_cast<std::uint64_t>(k);
    BeyondTolerance& b = ranked[static_cast<std::size_t>(k)];
    b = fit_on(problem, id, within_tolerances_without(problem, nominal, options, within, id), nominal_device, options,
               seed);
    score(problem, w, trials, options, seed, b);
  });
  sort_by_training_error(ranked);
  // The best few refitted jointly with every tolerance: an effect's share of what the tolerances took is its own.
  // Not where the leader already closes nearly all of the gap they leave (each refit costs a tolerance fit).
  const bool settled = !ranked.empty() && ranked.front().explained_fraction >= kSettled;
  const std::size_t joint =
      settled ? 0
              : std::min<std::size_t>(static_cast<std::size_t>(std::max(0, options.beyond_joint_candidates)),
                                      ranked.size());
  for (std::size_t k = 0; k < joint; ++k) {  // one at a time: the least squares spreads its Jacobian over the jobs
    BeyondTolerance& b = ranked[k];
    const JointFit fit = fit_effect_within_tolerances(problem, nominal, options, within, b.id, b.values);
    BeyondTolerance refitted = b;
    refitted.values = fit.values;
    refitted.params = describe_values(b.id, fit.values, nominal_device);
    refitted.variant.emplace(fit.variant);
    refitted.joint = true;
    refitted.evaluations += fit.evaluations;
    score(problem, w, trials, options, options.seed + 3000 + k, refitted);
    if (refitted.train_error_with_effect < b.train_error_with_effect) {
      b = std::move(refitted);
    } else {
      b.evaluations = refitted.evaluations;
    }
  }
  sort_by_training_error(ranked);
  return ranked;
}

std::optional<BeyondTolerance> second_beyond_tolerances(const GapProblem& problem,
                                                        const sim::DeviceDescription& nominal_device,
                                                        const ToleranceFit& within,
                                                        const std::vector<TrialGap>& trials,
                                                        const std::vector<BeyondTolerance>& ranked,
                                                        const DiagnosisOptions& options) {
  if (ranked.size() < 2 || !ranked.front().variant) return std::nullopt;
  const Within w = within_of(problem, within);
  const UnitSums first = problem.heldout_sums(problem.evaluate(*ranked.front().variant, false));
  const std::size_t count = std::min<std::size_t>(2, ranked.size() - 1);
  std::vector<BeyondTolerance> tries(count);
  parallel_for(static_cast<int>(count), options.jobs, [&](int k) {
    const std::uint64_t seed = options.seed + 4000 + static_cast<std::uint64_t>(k);
    BeyondTolerance& b = tries[static_cast<std::size_t>(k)];
    b = fit_on(problem, ranked[static_cast<std::size_t>(k) + 1].id, *ranked.front().variant, nominal_device, options,
               seed);
    score(problem, w, trials, options, seed, b);
  });
  sort_by_training_error(tries);
  BeyondTolerance& second = tries.front();
  // Its interval: of the cut it makes in what the first leaves.
  std::tie(second.ci_low, second.ci_high) =
      bootstrap_interval(problem, first, problem.heldout_sums(problem.evaluate(*second.variant, false)),
                         options.bootstrap, options.seed + 4100);
  return second;
}

}  // namespace softwrist::diagnosis
