#include "diagnosis/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "common/parallel_for.h"
#include "diagnosis/effect_fit.h"
#include "diagnosis/gap_problem.h"

namespace softwrist::diagnosis {
namespace {

std::runtime_error nothing_left(const Diagnosis& d) {
  return std::runtime_error(d.problems.empty()
                                ? std::string("no trial logs found to diagnose (softwrist.log/1 sidecars)")
                                : "no trial left to diagnose (see the problems listed above)");
}

// Trials the model cannot replay are reported and left out; so is a trial whose noise cannot be estimated (constant
// data), which cannot be weighed against the others. Fills d.data.trials and d.prepared.
void prepare_trials(Diagnosis& d, ReplayEngine& engine, const ModelVariant& nominal) {
  std::vector<Trial> replayable;
  for (Trial& trial : d.data.trials) {
    try {
      engine.check_replayable(trial, nominal);
      replayable.push_back(std::move(trial));
    } catch (const std::exception& e) {
      d.problems.push_back({trial.file, e.what()});
    }
  }
  d.data.trials = std::move(replayable);
  if (d.data.trials.empty()) throw nothing_left(d);
  d.prepared = prepare(d.data, engine, nominal);
  for (auto it = d.prepared.begin(); it != d.prepared.end();) {
    if (!(it->noise > 0.0)) {
      d.problems.push_back(
          {it->trial->file, fmt::format("{}: its repeat-to-repeat noise is zero; it cannot be weighed", it->name)});
      it = d.prepared.erase(it);
    } else {
      ++it;
    }
  }
  if (d.prepared.empty()) throw nothing_left(d);
}

double rms(const std::vector<double>& r) {
  double ss = 0.0;
  for (double v : r) ss += v * v;
  return std::sqrt(ss / static_cast<double>(r.size()));
}

// A trial's whole gap test (localization's "all").
LocalizationEntry trial_test(const PreparedTrial& trial, const std::vector<double>& residuals) {
  std::vector<std::size_t> all(residuals.size());
  std::iota(all.begin(), all.end(), 0);
  return group_test(trial, residuals, all);
}

// Each trial's gap with the nominal model, significant at alpha Bonferroni-corrected over the trials.
std::vector<TrialGap> nominal_trial_gaps(const std::vector<PreparedTrial>& prepared,
                                         const std::vector<std::vector<double>>& residuals, double trial_alpha) {
  std::vector<TrialGap> gaps;
  for (std::size_t t = 0; t < prepared.size(); ++t) {
    const LocalizationEntry e = trial_test(prepared[t], residuals[t]);
    const PreparedTrial& p = prepared[t];
    TrialGap gap{.experiment = p.name,
                 .kind = p.trial->kind,
                 .unit = p.unit,
                 .noise = p.noise,
                 .noise_source = p.noise_source,
                 .p_value = e.p_value,
                 .significant = e.p_value < trial_alpha,
                 .points = p.points.size()};
    gap.rms_nominal = rms(residuals[t]);
    gaps.push_back(gap);
  }
  return gaps;
}

// Each effect alone on the nominal model, best first (applicable ones before the others).
std::vector<EffectFit> fit_each_effect(const GapProblem& problem, const BaseModel& nominal,
                                       const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options) {
  std::vector<EffectId> ids = options.effects;
  if (ids.empty()) {
    for (const auto& spec : effect_catalogue()) ids.push_back(spec.id);
  }
  std::vector<EffectFit> fits(ids.size());
  parallel_for(static_cast<int>(ids.size()), options.jobs, [&](int k) {
    fits[static_cast<std::size_t>(k)] = fit_effect(problem, ids[static_cast<std::size_t>(k)], nominal, nominal_device,
                                                   options, options.seed + static_cast<std::uint64_t>(k));
  });
  std::stable_sort(fits.begin(), fits.end(), [](const EffectFit& a, const EffectFit& b) {
    if (a.applicable != b.applicable) return a.applicable;
    return a.score > b.score;
  });
  return fits;
}

struct Combination {
  std::vector<EffectFit> effects;  // in the order they joined
  ModelVariant model;
  Predictions full;  // its predictions on all the data
};

// Greedy combination: the best effect first, then whichever of the next candidates cuts the remaining held-out
// error most, while each cut is at least min_gain of it and its bootstrap interval stays above zero.
Combination combine_greedily(const GapProblem& problem, const std::vector<EffectFit>& single_fits,
                             const ModelVariant& nominal, const Predictions& nominal_training,
                             const Predictions& nominal_full, const sim::DeviceDescription& nominal_device,
                             const DiagnosisOptions& options) {
  const auto helps = [&](const EffectFit& f) {
    return f.applicable && f.shrink_fraction >= options.min_gain && f.ci_low > 0.0;
  };
  Combination c{.effects = {}, .model = nominal, .full = nominal_full};
  Predictions current_training = nominal_training;
  std::vector<EffectId> candidates;
  for (const auto& f : single_fits) {
    if (helps(f)) candidates.push_back(f.id);
  }
  std::uint64_t round_seed = options.seed + 1000;
  while (!candidates.empty() && static_cast<int>(c.effects.size()) < options.max_combined) {
    std::vector<EffectFit> tries;
    if (c.effects.empty()) {
      tries.push_back(*std::find_if(single_fits.begin(), single_fits.end(),
                                    [&](const EffectFit& f) { return f.id == candidates.front(); }));
    } else {
      const std::size_t count = std::min<std::size_t>(3, candidates.size());
      tries.resize(count);
      const BaseModel current{.variant = c.model, .training = current_training, .full = c.full};
      parallel_for(static_cast<int>(count), options.jobs, [&](int k) {
        tries[static_cast<std::size_t>(k)] =
            fit_effect(problem, candidates[static_cast<std::size_t>(k)], current, nominal_device, options,
                       round_seed + static_cast<std::uint64_t>(k));
      });
      round_seed += 100;
    }
    const auto best = std::max_element(tries.begin(), tries.end(),
                                       [](const EffectFit& a, const EffectFit& b) { return a.score < b.score; });
    if (!helps(*best)) break;
    apply_effect(best->id, best->values, c.model);
    candidates.erase(std::find(candidates.begin(), candidates.end(), best->id));
    c.effects.push_back(*best);
    current_training = problem.evaluate(c.model, true);
    c.full = problem.evaluate(c.model, false);
  }
  return c;
}

// The corrected model's errors: over all trials, over the trials whose nominal gap is significant (the others only
// add their noise floor, which no effect removes), and each trial's remaining residual and its test.
void measure_correction(Diagnosis& d, const GapProblem& problem, const Predictions& nominal_full,
                        const Predictions& corrected_full, double trial_alpha) {
  d.heldout_corrected = problem.heldout_error(problem.heldout_sums(corrected_full));
  std::vector<bool> gap_trials;
  for (const auto& t : d.trials) gap_trials.push_back(t.significant);
  d.gap_nominal = problem.heldout_error(problem.heldout_sums(nominal_full), nullptr, &gap_trials);
  d.gap_corrected = problem.heldout_error(problem.heldout_sums(corrected_full), nullptr, &gap_trials);
  for (std::size_t t = 0; t < problem.size(); ++t) {
    const std::vector<double> r = residuals_of(d.prepared[t], corrected_full[t]);
    d.trials[t].rms_corrected = rms(r);
    d.remaining_gap_significant = d.remaining_gap_significant || trial_test(d.prepared[t], r).p_value < trial_alpha;
  }
}

void decide_verdict(Diagnosis& d, bool gap_significant, const DiagnosisOptions& options) {
  const double closed = d.gap_closed();
  if (!gap_significant) {
    d.verdict = "none";
    d.reason = fmt::format(
        "no trial differs from the nominal model beyond its repeat-to-repeat noise (F test, "
        "alpha {} over {} trials)",
        options.alpha, d.prepared.size());
  } else if (d.heldout_nominal < options.min_gap) {
    d.verdict = "none";
    d.reason = fmt::format(
        "the nominal model's systematic residual is {:.2f} of the noise on held-out data (below "
        "{}): detectable in this much data, but within the noise of a measurement",
        d.heldout_nominal, options.min_gap);
  } else if (!d.combination.empty() && closed >= options.explained_fraction) {
    d.verdict = d.combination.front().name;
    d.reason = fmt::format("{} closes {:.0f} % of the held-out gap on its own ({:.0f} % with the combination)",
                           d.combination.front().name, 100.0 * d.combination.front().shrink_fraction, 100.0 * closed);
  } else {
    d.verdict = "unexplained";
    d.reason =
        d.combination.empty()
            ? "the gap is significant and no catalogue effect reduces the held-out error meaningfully"
            : fmt::format("the gap is significant and the best combination closes only {:.0f} % of it", 100.0 * closed);
  }
}

}  // namespace

Diagnosis diagnose(RealData data, const sim::DeviceDescription& nominal_device, ReplayEngine& engine,
                   const DiagnosisOptions& options) {
  Diagnosis d;
  d.data = std::move(data);
  d.problems = d.data.problems;
  const ModelVariant nominal{.device = nominal_device};
  prepare_trials(d, engine, nominal);
  GapProblem problem(d.prepared, engine);

  // Replay with the nominal model; localise; test each trial's gap.
  const Predictions nominal_full = problem.evaluate(nominal, false);
  const Predictions nominal_training = problem.evaluate(nominal, true);
  d.nominal_predictions = nominal_full;
  std::vector<std::vector<double>> residuals;
  for (std::size_t t = 0; t < problem.size(); ++t) residuals.push_back(residuals_of(d.prepared[t], nominal_full[t]));
  d.localization = localize(d.prepared, residuals, nominal_device, options.alpha);
  d.heldout_nominal = problem.heldout_error(problem.heldout_sums(nominal_full));
  const double trial_alpha = options.alpha / static_cast<double>(problem.size());
  d.trials = nominal_trial_gaps(d.prepared, residuals, trial_alpha);
  const bool gap_significant =
      std::any_of(d.trials.begin(), d.trials.end(), [](const TrialGap& t) { return t.significant; });

  // Attribute: each effect alone, then the greedy combination; measure the corrected model; decide.
  d.effects = fit_each_effect(problem, {.variant = nominal, .training = nominal_training, .full = nominal_full},
                              nominal_device, options);
  Combination combination =
      combine_greedily(problem, d.effects, nominal, nominal_training, nominal_full, nominal_device, options);
  d.combination = std::move(combination.effects);
  d.corrected.emplace(combination.model);
  d.corrected_predictions = combination.full;
  measure_correction(d, problem, nominal_full, combination.full, trial_alpha);
  decide_verdict(d, gap_significant, options);
  return d;
}

}  // namespace softwrist::diagnosis
