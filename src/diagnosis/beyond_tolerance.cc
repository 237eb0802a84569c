#include "diagnosis/beyond_tolerance.h"

#include <algorithm>
#include <array>
#include <tuple>

#include "common/parallel_for.h"
#include "diagnosis/tolerance_fit.h"

namespace softwrist::diagnosis {
namespace {

using BeyondTolerance = Diagnosis::BeyondTolerance;

// The share of the held-out gap beyond the tolerances above which only the leader is refitted jointly with them.
constexpr double kSettled = 0.9;

// The tolerance fit's model and its errors: what every effect is measured against.
struct Within {
  Predictions full;
  UnitSums sums;
  double train_error = 0.0;
};

Within within_of(const GapProblem& problem, const ToleranceFit& within) {
  Within w{.full = within.full.empty() ? problem.evaluate(*within.variant, false) : within.full};
  w.sums = problem.heldout_sums(w.full);
  w.train_error = problem.training_error(problem.evaluate(*within.variant, true));
  return w;
}

// b's errors and fractions with its model (b.variant) against `reference` (held-out sums): for an effect alone, the
// nominal within every tolerance but the effect's own, whose box is part of the effect's range (an fPAM 8 % wider
// than placed is 3 % within its tolerance and 5 % beyond it; measured against the whole tolerance fit, the 3 % would
// count as no one's, and what is left beyond it is mostly the part of the effect's form the catalogue's lacks).
void score(const GapProblem& problem, const Within& w, const UnitSums& reference, const std::vector<TrialGap>& trials,
           const DiagnosisOptions& options, std::uint64_t seed, BeyondTolerance& b) {
  b.train_error_within = w.train_error;
  b.train_error_with_effect = problem.training_error(problem.evaluate(*b.variant, true));
  const UnitSums after = problem.heldout_sums(problem.evaluate(*b.variant, false));
  b.heldout_error_within = problem.heldout_error(reference);
  b.heldout_error_with_effect = problem.heldout_error(after);
  b.explained_fraction = fraction_closed(b.heldout_error_within, b.heldout_error_with_effect);
  const std::vector<bool> acted_on = gap_trials_acted_on(problem, trials, effect_spec(b.id));
  if (std::any_of(acted_on.begin(), acted_on.end(), [](bool a) { return a; })) {
    b.explained_in_acted_on = fraction_closed(problem.heldout_error(reference, nullptr, &acted_on),
                                              problem.heldout_error(after, nullptr, &acted_on));
  }
  std::tie(b.ci_low, b.ci_high) = bootstrap_interval(problem, reference, after, options.bootstrap, seed);
}

// Effect `id` fitted on `base` (its own parameters searched as fit_effect does; the base held); the base's held-out
// sums in *base_sums.
BeyondTolerance fit_on(const GapProblem& problem, EffectId id, const ModelVariant& base,
                       const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options,
                       std::uint64_t seed, UnitSums* base_sums = nullptr) {
  const Predictions training = problem.evaluate(base, true), full = problem.evaluate(base, false);
  if (base_sums != nullptr) *base_sums = problem.heldout_sums(full);
  const EffectFit fit =
      fit_effect(problem, id, {.variant = base, .training = training, .full = full}, nominal_device, options, seed);
  BeyondTolerance b{.id = id, .effect = fit.name, .values = fit.values, .params = fit.params};
  b.evaluations = fit.evaluations + 2;
  b.variant.emplace(base);
  apply_effect(id, fit.values, *b.variant);
  return b;
}

std::vector<EffectId> applicable_effects(const GapProblem& problem, const DiagnosisOptions& options) {
  std::vector<EffectId> ids = requested_effects(options);
  std::erase_if(ids, [&](EffectId id) {
    const EffectSpec& spec = effect_spec(id);
    return std::none_of(problem.trials().begin(), problem.trials().end(),
                        [&](const PreparedTrial& t) { return acts_on(spec, t); });
  });
  return ids;
}

void sort_by_training_error(std::vector<BeyondTolerance>& ranked) {
  std::stable_sort(ranked.begin(), ranked.end(), [](const BeyondTolerance& a, const BeyondTolerance& b) {
    return a.train_error_with_effect < b.train_error_with_effect;
  });
}

}  // namespace

std::vector<BeyondTolerance> rank_beyond_tolerances(const GapProblem& problem, const BaseModel& as_placed,
                                                    const sim::DeviceDescription& nominal_device,
                                                    const ToleranceFit& within, const std::vector<TrialGap>& trials,
                                                    const DiagnosisOptions& options) {
  if (within.params.empty() || !within.variant) return {};
  const ModelVariant& nominal = as_placed.variant;
  const Within w = within_of(problem, within);
  const std::vector<EffectId> ids = applicable_effects(problem, options);
  std::vector<BeyondTolerance> ranked(ids.size());
  std::vector<UnitSums> references(ids.size());
  parallel_for(static_cast<int>(ids.size()), options.jobs, [&](int k) {
    const auto i = static_cast<std::size_t>(k);
    const std::uint64_t seed = options.seed + 2000 + i;
    ranked[i] = fit_on(problem, ids[i], within_tolerances_without(problem, nominal, options, within, {&ids[i], 1}),
                       nominal_device, options, seed, &references[i]);
    score(problem, w, references[i], trials, options, seed, ranked[i]);
  });
  const auto reference_of = [&](EffectId id) -> const UnitSums& {
    return references[static_cast<std::size_t>(std::find(ids.begin(), ids.end(), id) - ids.begin())];
  };
  sort_by_training_error(ranked);
  // The best few refitted jointly with every tolerance: an effect's share of what the tolerances took is its own
  // (fitted on them as they were fitted, an IMU offset of 2 deg came out 1.71). Only the leader where it already
  // closes nearly all of the gap they leave: no refit of another could overtake it, and each costs a tolerance fit.
  const bool settled = !ranked.empty() && ranked.front().explained_fraction >= kSettled;
  const std::size_t joint = std::min<std::size_t>(
      settled ? 1 : static_cast<std::size_t>(std::max(0, options.beyond_joint_candidates)), ranked.size());
  for (std::size_t k = 0; k < joint; ++k) {  // one at a time: the least squares spreads its Jacobian over the jobs
    BeyondTolerance& b = ranked[k];
    const EffectFit from_placed =
        fit_effect(problem, b.id, as_placed, nominal_device, options, options.seed + 2500 + k);
    const JointFit fit =
        fit_effect_within_tolerances(problem, nominal, options, within, b.id, b.values, from_placed.values);
    BeyondTolerance refitted = b;
    refitted.values = fit.values;
    refitted.params = describe_values(b.id, fit.values, nominal_device);
    refitted.variant.emplace(fit.variant);
    refitted.tolerances = fit.tolerances;
    refitted.joint = true;
    refitted.evaluations += from_placed.evaluations + fit.evaluations;
    score(problem, w, reference_of(b.id), trials, options, options.seed + 3000 + k, refitted);
    if (refitted.train_error_with_effect < b.train_error_with_effect) {
      b = std::move(refitted);
    } else {
      b.evaluations = refitted.evaluations;
    }
  }
  sort_by_training_error(ranked);
  return ranked;
}

std::optional<BeyondTolerance> second_beyond_tolerances(const GapProblem& problem, const ModelVariant& nominal,
                                                        const sim::DeviceDescription& nominal_device,
                                                        const ToleranceFit& within, const std::vector<TrialGap>& trials,
                                                        const std::vector<BeyondTolerance>& ranked,
                                                        const DiagnosisOptions& options) {
  if (ranked.size() < 2 || !ranked.front().variant) return std::nullopt;
  const Within w = within_of(problem, within);
  const UnitSums first = problem.heldout_sums(problem.evaluate(*ranked.front().variant, false));
  // The candidates: the other effects that close min_gain of the held-out gap on their own, the two that close most
  // (a pre-screen on the held-out part, as the greedy combination's; between them the training error chooses). Not
  // by the training error of their values added to the leader's model: an fPAM's r0 scale fitted without its
  // tolerance, added to a model that has it, counts it twice.
  std::vector<std::pair<double, EffectId>> candidates;
  for (std::size_t k = 1; k < ranked.size(); ++k) {
    if (ranked[k].explained_fraction >= options.min_gain)
      candidates.emplace_back(-ranked[k].explained_fraction, ranked[k].id);
  }
  if (candidates.empty()) return std::nullopt;
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  const std::size_t count = std::min<std::size_t>(2, candidates.size());
  std::vector<BeyondTolerance> tries(count);
  parallel_for(static_cast<int>(count), options.jobs, [&](int k) {
    const std::uint64_t seed = options.seed + 4000 + static_cast<std::uint64_t>(k);
    BeyondTolerance& b = tries[static_cast<std::size_t>(k)];
    // On the leader's model with the candidate's own tolerance back at the nominal (else an fPAM's r0 scale would
    // count its tolerance twice).
    const BeyondTolerance& lead = ranked.front();
    const std::array ids{lead.id, candidates[static_cast<std::size_t>(k)].second};
    ModelVariant base = within_tolerances_without(problem, nominal, options, within, ids, lead.tolerances);
    apply_effect(lead.id, lead.values, base);
    b = fit_on(problem, ids[1], base, nominal_device, options, seed);
    score(problem, w, w.sums, trials, options, seed, b);
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
