#include "diagnosis/second_effect.h"

#include <algorithm>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "common/parallel_for.h"

namespace softwrist::diagnosis {
namespace {

// Where a second effect, with `with_second` the held-out residuals per trial, acts where the leader cannot: the gap
// trial it cuts most among those the leader left (trials_the_leader_left), and that cut; none below contradiction_gap.
struct SecondEvidence {
  std::size_t trial = 0;
  double cut = 0.0;
};
std::optional<SecondEvidence> acts_where_the_leader_cannot(const Diagnosis& d, const std::vector<bool>& left,
                                                           const std::vector<double>& with_second,
                                                           const DiagnosisOptions& options) {
  const std::vector<double>& lead = d.combination.front().heldout_excess_by_trial;
  if (with_second.size() != lead.size()) return std::nullopt;
  std::optional<SecondEvidence> best;
  for (std::size_t t = 0; t < left.size(); ++t) {
    const double cut = lead[t] - with_second[t];
    if (left[t] && cut >= options.contradiction_gap && (!best || cut > best->cut)) best = SecondEvidence{t, cut};
  }
  return best;
}

}  // namespace

std::vector<double> heldout_excess_by_trial(const GapProblem& problem, const UnitSums& sums) {
  if (sums.per_trial.size() != problem.size()) return {};
  std::vector<double> excess(problem.size(), 0.0);
  for (std::size_t t = 0; t < problem.size(); ++t) {
    std::vector<bool> only(problem.size(), false);
    only[t] = true;
    excess[t] = problem.heldout_error(sums, nullptr, &only);
  }
  return excess;
}

std::vector<bool> trials_the_leader_left(const Diagnosis& d, const DiagnosisOptions& options) {
  std::vector<bool> left(d.trials.size(), false);
  if (d.combination.empty() || d.combination.front().heldout_excess_by_trial.size() != d.trials.size()) return left;
  const std::vector<double>& lead = d.combination.front().heldout_excess_by_trial;
  for (std::size_t t = 0; t < d.trials.size(); ++t) {
    const bool untouched =
        lead[t] >= (1.0 - options.second_untouched_fraction) * d.trials[t].heldout_excess_leader_base;
    left[t] = d.trials[t].gap && untouched && lead[t] >= options.contradiction_gap;
  }
  return left;
}

std::vector<EffectFit> fit_seconds_where_untouched(const Diagnosis& d, const GapProblem& problem,
                                                   const SecondBase& base_of, const sim::DeviceDescription& nominal,
                                                   const DiagnosisOptions& options) {
  const std::vector<bool> left = trials_the_leader_left(d, options);
  if (std::none_of(left.begin(), left.end(), [](bool b) { return b; })) return {};
  std::vector<EffectId> ids;
  for (const EffectFit& f : d.effects) {
    if (!f.applicable || f.id == d.combination.front().id) continue;
    const std::vector<bool> acted_on = gap_trials_acted_on(problem, d.trials, effect_spec(f.id));
    for (std::size_t t = 0; t < left.size(); ++t) {
      if (left[t] && acted_on[t]) {
        ids.push_back(f.id);
        break;
      }
    }
  }
  std::vector<ModelVariant> bases;
  for (EffectId id : ids) bases.push_back(base_of(id));
  std::vector<EffectFit> fits(ids.size());
  parallel_for(static_cast<int>(ids.size()), options.jobs, [&](int i) {
    const auto k = static_cast<std::size_t>(i);
    const Predictions training = problem.evaluate(bases[k], true), full = problem.evaluate(bases[k], false);
    fits[k] = fit_effect(problem, ids[k], {.variant = bases[k], .training = training, .full = full}, nominal, options,
                         options.seed + 5000 + 10 * k);
    fits[k].heldout_excess_by_trial = heldout_excess_by_trial(problem, fits[k].heldout_after_sums);
  });
  return fits;
}

void report_second_effect(Diagnosis& d, const DiagnosisOptions& options) {
  const std::vector<bool> left = trials_the_leader_left(d, options);
  std::vector<const EffectFit*> seconds;
  if (d.combination.size() >= 2) seconds.push_back(&d.combination[1]);
  for (const EffectFit& f : d.seconds_where_untouched) seconds.push_back(&f);
  const EffectFit* second = nullptr;
  std::optional<SecondEvidence> evidence;
  for (const EffectFit* f : seconds) {
    const auto e = acts_where_the_leader_cannot(d, left, f->heldout_excess_by_trial, options);
    if (e && (!evidence || e->cut > evidence->cut)) {
      evidence = e;
      second = f;
    }
  }
  if (second == nullptr) return;
  const std::size_t t = evidence->trial;
  d.also_effects = {second->name};
  d.reason += fmt::format(
      "; {} acts besides: {} keeps {:.2f} held-out noise units with {} ({:.2f} before it), {:.2f} with {} too",
      second->name, d.trials[t].experiment, d.combination.front().heldout_excess_by_trial[t], d.leading_effect,
      d.trials[t].heldout_excess_leader_base, second->heldout_excess_by_trial[t], second->name);
}

}  // namespace softwrist::diagnosis
