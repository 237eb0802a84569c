#include "diagnosis/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <future>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/parallel_for.h"
#include "diagnosis/beyond_tolerance.h"
#include "diagnosis/effect_fit.h"
#include "diagnosis/gap_problem.h"
#include "diagnosis/joint_refit.h"
#include "diagnosis/repeat_noise.h"
#include "diagnosis/setting_scatter.h"
#include "diagnosis/tolerance.h"
#include "diagnosis/tolerance_fit.h"
#include "physics/errors.h"

namespace softwrist::diagnosis {
namespace {

std::runtime_error nothing_left(const Diagnosis& d) {
  return std::runtime_error(d.problems.empty()
                                ? std::string("no trial logs found to diagnose (softwrist.log/1 sidecars)")
                                : "no trial left to diagnose (see the problems listed above)");
}

// The trials' points, noise and splits (prepare): the noise of a task repeated comes from the nominal's residuals.
void prepare_points(Diagnosis& d, ReplayEngine& engine, const ModelVariant& nominal) {
  d.prepared = prepare(d.data, engine, nominal);
  for (auto it = d.prepared.begin(); it != d.prepared.end();) {
    if (!(it->noise > 0.0)) {
      // Reported once, though the trials are prepared again where the routing changes (apply_routing).
      const FileProblem problem{it->trial->file,
                                fmt::format("{}: its repeat-to-repeat noise is zero; it cannot be weighed", it->name)};
      const auto same = [&](const FileProblem& p) { return p.file == problem.file && p.reason == problem.reason; };
      if (std::none_of(d.problems.begin(), d.problems.end(), same)) d.problems.push_back(problem);
      it = d.prepared.erase(it);
    } else {
      ++it;
    }
  }
  if (d.prepared.empty()) throw nothing_left(d);
}

// Trials the model cannot replay are reported and left out (a rig's placement file that cannot be read, a pressure
// beyond the regulators); so is a trial whose noise cannot be estimated (constant data), which cannot be weighed
// against the others. Loads each rig the trials name into `nominal`; fills d.data.trials and d.prepared.
void prepare_trials(Diagnosis& d, ReplayEngine& engine, ModelVariant& nominal) {
  std::vector<Trial> replayable;
  for (Trial& trial : d.data.trials) {
    try {
      const auto& placement = trial.conventions.placement;
      if (!placement.empty() && !nominal.rigs.contains(placement))
        nominal.rigs.emplace(placement, sim::load_device(placement));
      engine.check_replayable(trial, nominal);
      replayable.push_back(std::move(trial));
    } catch (const std::exception& e) {
      d.problems.push_back({trial.file, e.what()});
    }
  }
  d.data.trials = std::move(replayable);
  if (d.data.trials.empty()) throw nothing_left(d);
  prepare_points(d, engine, nominal);
}

// The routings to diagnose with, in order (DiagnosisOptions::routing): the one fixed; or the one whose nominal as
// placed replays the trials the routing changes better first (ties to the nominal placement file's), and the other
// too where the two are within a factor kRoutingClear of each other: an effect's misfit, the same under either
// routing, then hides the difference the routing makes (a device with stretching mounts diagnosed on a rigid nominal,
// over all trials: 546 against 568, the routing it was simulated with second; without the effect 0.9 against 151).
// Only the range of motion and trajectories replay in MuJoCo: without them the file's routing alone.
constexpr double kRoutingClear = 2.0;

// The trials the routing changes: what MuJoCo replays, the range of motion and the trajectories' angles (the others
// would only dilute a comparison of the routings, or let the luck of a search on them decide it).
std::vector<PreparedTrial> trials_the_routing_changes(const std::vector<PreparedTrial>& prepared) {
  std::vector<PreparedTrial> in_mujoco;
  std::copy_if(prepared.begin(), prepared.end(), std::back_inserter(in_mujoco), [](const PreparedTrial& t) {
    return !t.pressures && (t.trial->kind == TrialKind::kRangeOfMotion || t.trial->kind == TrialKind::kTrajectory);
  });
  return in_mujoco;
}

std::vector<sim::Routing> routings_to_try(Diagnosis& d, ReplayEngine& engine, const ModelVariant& nominal,
                                          const DiagnosisOptions& options) {
  if (options.routing) return {*options.routing};
  const sim::Routing filed = nominal.device.routing;
  std::vector<PreparedTrial> in_mujoco = trials_the_routing_changes(d.prepared);
  if (in_mujoco.empty()) return {filed};
  const sim::Routing other = filed == sim::Routing::kSpatial ? sim::Routing::kPlanar : sim::Routing::kSpatial;
  GapProblem probe(in_mujoco, engine);
  for (const sim::Routing routing : {filed, other}) {
    ModelVariant routed = nominal;
    routed.route(routing);
    d.routing_training_error.emplace_back(routing, probe.training_error(probe.evaluate(routed, true)));
  }
  const double e_filed = d.routing_training_error[0].second, e_other = d.routing_training_error[1].second;
  const std::vector<sim::Routing> order = e_other < e_filed ? std::vector{other, filed} : std::vector{filed, other};
  if (std::max(e_filed, e_other) > kRoutingClear * std::min(e_filed, e_other)) return {order.front()};
  return order;
}

// The nominal routed as chosen; the trials prepared again where that changes a rig's routing.
void apply_routing(Diagnosis& d, ReplayEngine& engine, ModelVariant& nominal, sim::Routing routing) {
  d.routing = routing;
  if (nominal.routed_as(routing)) return;
  nominal.route(routing);
  prepare_points(d, engine, nominal);
}

double rms(const std::vector<double>& r) {
  double ss = 0.0;
  for (double v : r) ss += v * v;
  return std::sqrt(ss / static_cast<double>(r.size()));
}

// The systematic part of residuals `r` in units of `noise`: sqrt(max(0, mean (r/noise)^2 - 1)). A sweep's residuals
// whitened for the scatter its settings share first (setting_scatter.h).
double excess_over_noise(const std::vector<double>& r, double noise) {
  const double in_noise_units = rms(r) / noise;
  return std::sqrt(std::max(0.0, in_noise_units * in_noise_units - 1.0));
}

std::vector<std::vector<double>> residuals_of_all(const std::vector<PreparedTrial>& prepared,
                                                  const Predictions& predictions) {
  std::vector<std::vector<double>> residuals;
  for (std::size_t t = 0; t < prepared.size(); ++t) residuals.push_back(residuals_of(prepared[t], predictions[t]));
  return residuals;
}

// A trial's whole gap test (localization's "all"), on its whitened residuals (setting_scatter.h).
LocalizationEntry trial_test(const PreparedTrial& trial, const std::vector<double>& white) {
  std::vector<std::size_t> all(white.size());
  std::iota(all.begin(), all.end(), 0);
  return group_test(trial, white, all);
}

// Each trial's gap with the nominal model: significant at family-wise rate alpha over the tests by Holm's step-down
// procedure (localization.h), which rejects at least what Bonferroni's alpha / tests does. A data set has one gap test
// per trial, and an effect that moves a whole experiment moves many trials at once: once the tensile test, the sweep
// and the pressures have rejected, an angle trial is tested at alpha over the tests left, not over all of them (the
// independent device's seed 38, an IMU 0.14 s late: 11 of 17 trials rejected first, and an ellipse 2.3 noise units off
// at p 0.0015 was then tested against 0.01 / 6, not Bonferroni's 0.01 / 17). Each repeated task is also tested whole,
// on its repetitions' mean (repeat_noise.h), and reported with each repetition; with `repeat_mean_test` that test
// joins the family, and a repetition is significant where its task is and the mean's systematic residual reaches
// min_gap (the error the repetitions share, not one repetition's wander).
std::vector<TrialGap> nominal_trial_gaps(const std::vector<PreparedTrial>& prepared,
                                         const std::vector<std::vector<double>>& residuals, double alpha,
                                         double min_gap, bool repeat_mean_test) {
  std::vector<TrialGap> gaps;
  std::vector<double> p_values;
  std::map<int, std::vector<std::size_t>> sets;
  for (std::size_t t = 0; t < prepared.size(); ++t) {
    const PreparedTrial& p = prepared[t];
    const std::vector<double> white = whitened(p, residuals[t]);
    const LocalizationEntry e = trial_test(p, white);
    TrialGap gap{.experiment = p.name,
                 .kind = p.trial->kind,
                 .unit = p.unit,
                 .noise = p.noise,
                 .noise_source = p.noise_source,
                 .p_value = e.p_value,
                 .points = p.points.size()};
    gap.rms_nominal = rms(residuals[t]);
    gap.excess_nominal = excess_over_noise(white, p.noise);
    gaps.push_back(gap);
    p_values.push_back(e.p_value);
    if (p.repeat_set >= 0) sets[p.repeat_set].push_back(t);
  }
  std::vector<std::pair<std::vector<std::size_t>, RepeatMeanTest>> tasks;
  for (const auto& [id, set] : sets) {
    if (set.size() < 2) continue;
    tasks.emplace_back(set, diagnosis::repeat_mean_test(prepared, residuals, set));
    if (repeat_mean_test) p_values.push_back(tasks.back().second.p_value);
  }
  const std::vector<bool> significant = holm_significant(p_values, alpha);
  for (std::size_t t = 0; t < gaps.size(); ++t) gaps[t].significant = significant[t];
  for (std::size_t k = 0; k < tasks.size(); ++k) {
    const auto& [set, test] = tasks[k];
    const bool task_gap = repeat_mean_test && significant[gaps.size() + k] && test.excess >= min_gap;
    for (std::size_t t : set) {
      gaps[t].repeat_p_value = test.p_value;
      gaps[t].repeat_excess = test.excess;
      gaps[t].significant = gaps[t].significant || task_gap;
    }
  }
  for (auto& gap : gaps) gap.gap = gap.gap_as_placed = gap.significant && gap.excess_nominal >= min_gap;
  return gaps;
}

// The nominal within its tolerances (tolerance.h), fitted where some trial has a gap from the nominal as placed: a
// trial whose gap the nominal closes anywhere within its tolerances has none (the nominal as placed is within them
// too, so a trial keeps its gap only if it differs from both).
void check_within_tolerances(Diagnosis& d, const GapProblem& problem, const ModelVariant& as_placed,
                             const DiagnosisOptions& options) {
  const bool any_gap = std::any_of(d.trials.begin(), d.trials.end(), [](const TrialGap& t) { return t.gap; });
  d.tolerance =
      any_gap ? fit_within_tolerances(problem, as_placed, options) : ToleranceFit{.tolerances = options.tolerances};
  d.tolerance.heldout_error_as_placed = d.tolerance.heldout_error_within = d.heldout_nominal;
  if (d.tolerance.params.empty()) return;
  d.tolerance.full = problem.evaluate(*d.tolerance.variant, false);
  d.tolerance.heldout_error_within = problem.heldout_error(problem.heldout_sums(d.tolerance.full));
  const std::vector<TrialGap> within = nominal_trial_gaps(d.prepared, residuals_of_all(d.prepared, d.tolerance.full),
                                                          options.alpha, options.min_gap, options.repeat_mean_test);
  for (std::size_t t = 0; t < d.trials.size(); ++t) {
    d.trials[t].excess_within_tolerance = within[t].excess_nominal;
    d.trials[t].repeat_excess_within_tolerance = within[t].repeat_excess;
    d.trials[t].gap = d.trials[t].gap && within[t].gap;
  }
}

// Where asked (EffectBase), the base each effect is fitted from: the nominal within its tolerances with the effect's
// own tolerance parameters back at the nominal, so that the effect takes its whole value (an fPAM 8 % wider than
// placed is 3 % within its r0 tolerance and 5 % beyond it: on the whole tolerance fit, the 3 % would be no one's).
struct OwnBases {
  std::vector<EffectId> ids;
  std::vector<ModelVariant> variants;
  std::vector<Predictions> training, full;
  std::size_t parameters = 0;  // the tolerance fit's
  BaseModel of(EffectId id, const BaseModel& otherwise) const {
    const auto it = std::find(ids.begin(), ids.end(), id);
    if (it == ids.end()) return otherwise;
    const auto k = static_cast<std::size_t>(it - ids.begin());
    return {.variant = variants[k], .training = training[k], .full = full[k]};
  }
};

OwnBases own_bases_within_tolerances(const Diagnosis& d, const GapProblem& problem, const ModelVariant& nominal,
                                     const DiagnosisOptions& options) {
  OwnBases own;
  if (!d.tolerance.variant) return own;
  own.ids = requested_effects(options);
  own.parameters = d.tolerance.params.size();
  for (const EffectId& id : own.ids)
    own.variants.push_back(within_tolerances_without(problem, nominal, options, d.tolerance, std::span(&id, 1), {}));
  own.training.resize(own.ids.size());
  own.full.resize(own.ids.size());
  parallel_for(static_cast<int>(own.ids.size()), options.jobs, [&](int i) {
    const auto k = static_cast<std::size_t>(i);
    own.training[k] = problem.evaluate(own.variants[k], true);
    own.full[k] = problem.evaluate(own.variants[k], false);
  });
  return own;
}

// The bases the effects are fitted from: the nominal as placed, its own base within the tolerances (OwnBases), or
// both, the fit with the lower held-out error kept (EffectBase::kBetterOfBoth). The bases within the tolerances are
// made only when fits need them (fit_each_effect).
struct EffectBases {
  const BaseModel& as_placed;
  std::function<OwnBases()> make_own;  // empty: from the nominal as placed only
  bool as_placed_too = true;
  OwnBases own;  // made by fit_each_effect where needed
  // The searches from the nominal as placed, where they have run already (search_from_base: requested_effects'
  // order).
  std::optional<std::vector<EffectSearch>> as_placed_searches;
  BaseModel of(const EffectFit& fit) const { return fit.within_tolerances ? own.of(fit.id, as_placed) : as_placed; }
};

// Each trial's held-out systematic residual in `sums` (noise units; 0 for a trial without held-out points).
std::vector<double> heldout_excess_by_trial(const GapProblem& problem, const UnitSums& sums) {
  std::vector<double> excess(problem.size(), 0.0);
  if (sums.per_trial.size() != problem.size()) return {};
  for (std::size_t t = 0; t < problem.size(); ++t) {
    std::vector<bool> only(problem.size(), false);
    only[t] = true;
    excess[t] = problem.heldout_error(sums, nullptr, &only);
  }
  return excess;
}

// The fits' extensions (extend_fit) where their base forms leave a gap: the lowest held-out error among `fits` still
// at least min_gap noise units, or a trial that the fit with it leaves min_gap noise units off. Where a base form
// closes the gap, no extension has anything left to explain, and none is searched (the paper-sized set: the mounts
// close it all, and the extensions' searches would add half its time). A mean below min_gap can hide a trial it does
// not close (seed 51's second_order_response: the first-order regulator fitted with the trials' starts leaves 0.97 over
// all trials and 1.9-4.2 noise units in each of seven trials' pressures, which its second order closes).
void extend_where_a_gap_remains(const GapProblem& problem, std::vector<EffectFit>& fits,
                                const std::function<BaseModel(const EffectFit&)>& base_of,
                                const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options,
                                std::uint64_t seed) {
  const EffectFit* lowest = nullptr;
  for (const EffectFit& f : fits) {
    if (f.applicable && (lowest == nullptr || f.heldout_error_after < lowest->heldout_error_after)) lowest = &f;
  }
  if (lowest == nullptr || !std::isfinite(lowest->heldout_error_after)) return;
  if (lowest->heldout_error_after < options.min_gap) {
    // Only the trials scored (those with a gap as placed): a trial the nominal matched asks for no extension.
    const std::vector<double> excess = heldout_excess_by_trial(problem, lowest->heldout_after_sums);
    bool trial_left = false;
    for (std::size_t t = 0; t < excess.size(); ++t)
      trial_left = trial_left || (problem.scored(t) && excess[t] >= options.min_gap);
    if (!trial_left) return;
  }
  parallel_for(static_cast<int>(fits.size()), options.jobs, [&](int k) {
    EffectFit& fit = fits[static_cast<std::size_t>(k)];
    extend_fit(problem, fit, base_of(fit), nominal_device, options, seed + static_cast<std::uint64_t>(k));
  });
}

// Each of `ids` searched on its base (search_effect), in parallel. Started longest first, so that the threads finish
// together (when the last one started was the longest, it took 15 of the paper's case's 25 s at commit c6c114f): the
// most parameters searched, and last those that replay only the regulators. The searches are independent, so the
// order changes nothing else.
std::vector<EffectSearch> search_from_base(const GapProblem& problem, const std::vector<EffectId>& ids,
                                           const std::function<BaseModel(EffectId)>& base_of,
                                           const DiagnosisOptions& options) {
  const auto cost = [&](EffectId id) {
    const EffectSpec& spec = effect_spec(id);
    return spec.through_regulators_only ? 0
                                        : std::count_if(spec.parameters.begin(), spec.parameters.end(),
                                                        [](const ParameterSpec& p) { return !p.extension; });
  };
  std::vector<std::size_t> order(ids.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cost(ids[a]) > cost(ids[b]); });
  std::vector<EffectSearch> searches(ids.size());
  parallel_for(static_cast<int>(order.size()), options.jobs, [&](int i) {
    const std::size_t k = order[static_cast<std::size_t>(i)];
    searches[k] = search_effect(problem, ids[k], base_of(ids[k]), options);
  });
  return searches;
}

// Each of `ids` fitted from the nominal as placed, or from its own base within the tolerances (searched here unless
// bases.as_placed_searches holds the searches as placed).
std::vector<EffectFit> fit_from_base(const GapProblem& problem, const std::vector<EffectId>& ids,
                                     const EffectBases& bases, bool within,
                                     const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options) {
  const auto base_of = [&](EffectId id) { return within ? bases.own.of(id, bases.as_placed) : bases.as_placed; };
  const std::vector<EffectSearch> searches = !within && bases.as_placed_searches
                                                 ? *bases.as_placed_searches
                                                 : search_from_base(problem, ids, base_of, options);
  std::vector<EffectFit> fits(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    EffectFit& fit = fits[k];
    fit = fit_effect(problem, ids[k], base_of(ids[k]), nominal_device, options, options.seed + k, &searches[k]);
    fit.within_tolerances = within;
    fit.base_parameters = within ? bases.own.parameters : 0;
  }
  return fits;
}

// Whether one of `fits` leaves no gap: a held-out error below min_gap noise units.
bool closes_the_gap(const std::vector<EffectFit>& fits, const DiagnosisOptions& options) {
  return std::any_of(fits.begin(), fits.end(),
                     [&](const EffectFit& f) { return f.applicable && f.heldout_error_after < options.min_gap; });
}

// Held-out units below which a bootstrap interval of the shrink is not asked for.
constexpr std::size_t kMinBootstrapUnits = 5;

// Whether a bootstrap interval of the shrink says anything: not when the trials with a gap hold few held-out units
// (a tensile test alone holds out two pressure levels, and resampling two units gives three possible data sets).
bool interval_informative(const GapProblem& problem) {
  std::size_t units = 0;
  const auto heldout_units = problem.heldout_units();
  for (std::size_t t = 0; t < problem.size(); ++t) units += problem.scored(t) ? heldout_units[t].size() : 0;
  return units >= kMinBootstrapUnits;
}

// Each effect alone on its bases (EffectBases): the leader first, then best first (applicable ones before the
// others). Of an effect fitted from two bases, the one with the lower held-out error over every trial. Where an effect
// from the nominal as placed already closes the gap, the bases within the tolerances are neither made nor fitted from:
// the most they could do is close it too, at the price of a tolerance fit's parameters (the paper-sized set: the mounts
// close it, and the second base would add half the replays).
std::vector<EffectFit> fit_each_effect(const GapProblem& problem, EffectBases& bases,
                                       const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options) {
  const std::vector<EffectId> ids = requested_effects(options);
  std::vector<EffectFit> tried;
  if (bases.as_placed_too || !bases.make_own)
    tried = fit_from_base(problem, ids, bases, false, nominal_device, options);
  if (bases.make_own && !closes_the_gap(tried, options)) {
    bases.own = bases.make_own();
    if (!bases.own.ids.empty()) {
      for (EffectFit& f : fit_from_base(problem, ids, bases, true, nominal_device, options))
        tried.push_back(std::move(f));
    } else if (tried.empty()) {
      tried = fit_from_base(problem, ids, bases, false, nominal_device, options);  // no tolerances to fit within
    }
  }
  // Of an effect's two fits, compared over every trial: one from the nominal as placed leaves a trial the tolerances
  // explain (no gap beyond them, so not scored) as it was, and over the scored trials alone it would not pay for that
  // (seed 22's glove_slide: wrap_geometry as placed led with a training error of 126 against 2 within them).
  const std::vector<bool> every(problem.size(), true);
  const auto on_every_trial = [&](const EffectFit& f) {
    return problem.heldout_error(f.heldout_after_sums, nullptr, &every);
  };
  std::vector<std::optional<EffectFit>> best(ids.size());
  for (std::size_t i = 0; i < tried.size(); ++i) {
    std::optional<EffectFit>& b = best[i % ids.size()];
    if (!b || (tried[i].applicable && (!b->applicable || on_every_trial(tried[i]) < on_every_trial(*b))))
      b = std::move(tried[i]);
  }
  std::vector<EffectFit> fits;
  for (auto& b : best) fits.push_back(std::move(*b));
  extend_where_a_gap_remains(
      problem, fits, [&](const EffectFit& f) { return bases.of(f); }, nominal_device, options, options.seed + 300);
  std::stable_sort(fits.begin(), fits.end(), [](const EffectFit& a, const EffectFit& b) {
    if (a.applicable != b.applicable) return a.applicable;
    return a.heldout_error_after < b.heldout_error_after;
  });
  const std::size_t leader =
      leader_of_single_fits(problem, fits, options, options.seed + 500, interval_informative(problem));
  if (leader < fits.size())
    std::rotate(fits.begin(), fits.begin() + static_cast<std::ptrdiff_t>(leader),
                fits.begin() + static_cast<std::ptrdiff_t>(leader) + 1);
  return fits;
}

// Each fit's share where it acts (EffectFit::shrink_where_acting), and its base form's where an extension replaced it:
// where it acts on no trial scored, over its trials with a gap as placed; otherwise shrink_fraction, as fitted.
void measure_shares_where_acting(std::vector<EffectFit>& fits, const GapProblem& problem,
                                 const std::vector<TrialGap>& trials, const EffectBases& bases) {
  for (EffectFit& f : fits) {
    if (!f.applicable) continue;
    const EffectSpec& spec = effect_spec(f.id);
    bool acts_on_scored = false;
    for (std::size_t t = 0; t < trials.size(); ++t)
      acts_on_scored = acts_on_scored || (problem.scored(t) && acts_on(spec, problem.trials()[t]));
    const std::vector<bool> differs = gap_trials_acted_on(problem, trials, spec, /*as_placed=*/true);
    if (acts_on_scored || std::none_of(differs.begin(), differs.end(), [](bool b) { return b; })) continue;
    const double before = problem.heldout_error(problem.heldout_sums(bases.of(f).full), nullptr, &differs);
    f.shrink_where_acting = fraction_closed(before, problem.heldout_error(f.heldout_after_sums, nullptr, &differs));
    if (f.base_form)
      f.base_form->shrink_where_acting =
          fraction_closed(before, problem.heldout_error(f.base_form->heldout_after_sums, nullptr, &differs));
  }
}

struct Combination {
  std::vector<EffectFit> effects;  // in the order they joined
  ModelVariant model;
  Predictions full;  // its predictions on all the data
};

// Where the combination is refitted jointly anyway (a calibration), an effect that does not help on top of it may
// still belong in it: one that joined earlier took its part while it was missing (a relaxed wrist fitted stiffer
// stands in for soft mounts, and the mounts then add nothing on top). Each try is added and the whole combination
// refitted together (joint_refit.h); the first whose joint model cuts the held-out error by min_gain, its bootstrap
// interval above zero (where informative), joins with the refitted values. Returns whether one joined.
bool join_with_refit(const GapProblem& problem, Combination& c, std::vector<EffectFit>& tries,
                     const ModelVariant& nominal, const DiagnosisOptions& options, bool informative,
                     std::uint64_t seed) {
  const UnitSums before = problem.heldout_sums(c.full);
  const double e0 = problem.heldout_error(before);
  if (!(e0 > 0.0)) return false;  // nothing left to cut
  for (EffectFit& t : tries) {
    if (!t.applicable) continue;
    std::vector<EffectFit> joint = c.effects;
    joint.push_back(t);
    ModelVariant model = refit_jointly(problem, joint, nominal, options);
    Predictions full = problem.evaluate(model, false);
    const UnitSums after = problem.heldout_sums(full);
    joint.back().heldout_error_before = e0;
    joint.back().heldout_error_after = problem.heldout_error(after);
    joint.back().shrink_fraction = joint.back().shrink_where_acting =
        fraction_closed(e0, joint.back().heldout_error_after);
    std::tie(joint.back().ci_low, joint.back().ci_high) =
        bootstrap_interval(problem, before, after, options.bootstrap, seed);
    if (joint.back().shrink_fraction < options.min_gain || (informative && !(joint.back().ci_low > 0.0))) continue;
    c.effects = std::move(joint);
    c.model = std::move(model);
    c.full = std::move(full);
    return true;
  }
  return false;
}

// Where the combination grows from the nominal within its tolerances (its leader was fitted there): that model with the
// own tolerance parameters of the given effects back at the nominal (within_tolerances_without). Empty: it grows from
// the nominal as placed.
using WithoutOwnTolerances = std::function<ModelVariant(std::span<const EffectId>)>;

// The base a try `id` is fitted on in a round after the first: the combination's model; or, grown within the
// tolerances, those with the own parameters of the combination's effects and of the try back at the nominal, and the
// combination's effects on top, so that the try takes its whole value as the leader did (a relaxed wrist that led from
// a base whose fPAM radius sat at its tolerance's edge left the fPAM 5 % wider only the last 2 %).
ModelVariant try_base(const Combination& c, EffectId id, const WithoutOwnTolerances& without_own) {
  if (!without_own) return c.model;
  std::vector<EffectId> ids;
  for (const EffectFit& e : c.effects) ids.push_back(e.id);
  ids.push_back(id);
  ModelVariant model = without_own(ids);
  for (const EffectFit& e : c.effects) apply_effect(e.id, e.values, model);
  return model;
}

// Greedy combination: the best effect first, then whichever of the next candidates cuts the remaining held-out
// error most, while each cut is at least min_gain of it and its bootstrap interval stays above zero (with a joint
// refit where the options ask for one, join_with_refit).
Combination combine_greedily(const GapProblem& problem, const std::vector<EffectFit>& single_fits,
                             const BaseModel& leader_base, const WithoutOwnTolerances& without_own,
                             const ModelVariant& nominal, const DiagnosisOptions& options) {
  const sim::DeviceDescription& nominal_device = nominal.device;
  const bool informative = interval_informative(problem);  // otherwise the cut alone
  const auto joins = [&](const EffectFit& f) { return joins_combination(f, informative, options); };
  Combination c{.effects = {}, .model = leader_base.variant, .full = leader_base.full};
  std::vector<EffectId> candidates;
  for (const auto& f : single_fits) {
    if (joins(f)) candidates.push_back(f.id);
  }
  std::uint64_t round_seed = options.seed + 1000;
  while (!candidates.empty() && static_cast<int>(c.effects.size()) < options.max_combined) {
    // Nothing left to cut: no try could close min_gain (> 0) of it, nor join with a refit, so none is fitted.
    if (!c.effects.empty() && options.min_gain > 0.0 && !(problem.heldout_error(problem.heldout_sums(c.full)) > 0.0))
      break;
    std::vector<EffectFit> tries;
    std::vector<ModelVariant> bases;  // each try's, after the first round
    if (c.effects.empty()) {
      tries.push_back(*std::find_if(single_fits.begin(), single_fits.end(),
                                    [&](const EffectFit& f) { return f.id == candidates.front(); }));
      bases.push_back(c.model);
    } else {
      const std::size_t count = std::min<std::size_t>(3, candidates.size());
      tries.resize(count);
      for (std::size_t k = 0; k < count; ++k) bases.push_back(try_base(c, candidates[k], without_own));
      // One base for all the tries, replayed once, unless each has its own.
      std::vector<Predictions> training(count), full(count, c.full);
      if (!without_own) training.assign(count, problem.evaluate(c.model, true));
      parallel_for(static_cast<int>(count), options.jobs, [&](int i) {
        const auto k = static_cast<std::size_t>(i);
        if (without_own) {
          training[k] = problem.evaluate(bases[k], true);
          full[k] = problem.evaluate(bases[k], false);
        }
        tries[k] = fit_effect(problem, candidates[k], {.variant = bases[k], .training = training[k], .full = full[k]},
                              nominal_device, options, round_seed + k);
      });
      const auto base_of = [&](const EffectFit& f) {
        const auto k =
            static_cast<std::size_t>(std::find(candidates.begin(), candidates.end(), f.id) - candidates.begin());
        return BaseModel{.variant = bases[k], .training = training[k], .full = full[k]};
      };
      extend_where_a_gap_remains(problem, tries, base_of, nominal_device, options, round_seed + 30);
      round_seed += 100;
    }
    // Of the tries that would join, the leader of the round; none joins when none helps.
    const std::size_t leader = leader_of_round(problem, tries, options, round_seed + 50, joins);
    if (leader < tries.size()) {
      const EffectFit& best = tries[leader];
      c.model = std::move(bases[leader]);
      apply_effect(best.id, best.values, c.model);
      c.effects.push_back(best);
      c.full = problem.evaluate(c.model, false);
    } else if (c.effects.empty() || options.joint_refit_evaluations <= 0 ||
               !join_with_refit(problem, c, tries, nominal, options, informative, round_seed + 70)) {
      break;
    }
    candidates.erase(std::find(candidates.begin(), candidates.end(), c.effects.back().id));
  }
  return c;
}

// The corrected model's errors: over all trials, over the trials whose nominal gap is significant (the others only
// add their noise floor, which no effect removes), and each trial's remaining residual and its test.
void measure_correction(Diagnosis& d, const GapProblem& problem, const Predictions& nominal_full,
                        const Predictions& corrected_full, double trial_alpha) {
  const std::vector<bool> all(problem.size(), true);
  d.heldout_corrected = problem.heldout_error(problem.heldout_sums(corrected_full), nullptr, &all);
  std::vector<bool> gap_trials;
  for (const auto& t : d.trials) gap_trials.push_back(t.gap);
  d.gap_nominal = problem.heldout_error(problem.heldout_sums(nominal_full), nullptr, &gap_trials);
  d.gap_corrected = problem.heldout_error(problem.heldout_sums(corrected_full), nullptr, &gap_trials);
  for (std::size_t t = 0; t < problem.size(); ++t) {
    const std::vector<double> r = residuals_of(d.prepared[t], corrected_full[t]);
    const std::vector<double> white = whitened(d.prepared[t], r);
    TrialGap& gap = d.trials[t];
    gap.rms_corrected = rms(r);
    gap.excess_corrected = excess_over_noise(white, d.prepared[t].noise);
    gap.remaining_significant = trial_test(d.prepared[t], white).p_value < trial_alpha;
    d.remaining_gap_significant = d.remaining_gap_significant || gap.remaining_significant;
  }
}

// Which trials the combination closes, member by member, and what its leader started from (for diagnosis.json and
// second_effect_trial).
void record_trials_closed(Diagnosis& d, const GapProblem& problem, const Predictions& leader_base_full) {
  const std::vector<double> base = heldout_excess_by_trial(problem, problem.heldout_sums(leader_base_full));
  for (std::size_t t = 0; t < base.size() && t < d.trials.size(); ++t) d.trials[t].heldout_excess_leader_base = base[t];
  for (EffectFit& f : d.combination) f.heldout_excess_by_trial = heldout_excess_by_trial(problem, f.heldout_after_sums);
}

// The held-out error, over `acted_on`, of `base` with `id` at `values` brought back into the effect's own tolerance
// box (tolerance_box; a parameter without a tolerance at its nominal value): what the tolerances alone reach of the
// effect's fit; `fitted_error` where that leaves the values as they are. Infinite where the effect has no box (its own
// base holds it at the nominal already; fit_start is no nominal for an effect the nominal lacks, as stretching mounts
// on a rigid nominal) or where the box's values do not make a valid model.
double heldout_error_in_own_box(const GapProblem& problem, const ModelVariant& base, EffectId id,
                                std::vector<double> values, double fitted_error,
                                const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options,
                                const std::vector<bool>& acted_on) {
  const auto box = tolerance_box(id, nominal_device, options.tolerances);
  if (!box) return std::numeric_limits<double>::infinity();
  bool moved = false;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double inside = std::clamp(values[i], (*box)[i].first, (*box)[i].second);
    moved = moved || inside != values[i];
    values[i] = inside;
  }
  if (!moved) return fitted_error;  // the fit ends inside its box: it closes nothing beyond it
  ModelVariant projected = base;
  try {
    apply_effect(id, values, projected);
  } catch (const physics::InvalidParameter&) {
    return std::numeric_limits<double>::infinity();
  }
  return problem.heldout_error(problem.heldout_sums(problem.evaluate(projected, false)), nullptr, &acted_on);
}

// How much of the held-out gap the leading effect closes on its own from the base it was fitted on, over the gap
// trials of the kinds it acts on; only what it closes beyond its own tolerance box counts (fitted from the nominal as
// placed, beyond the whole tolerance fit). Fitted from its own base (the tolerance fit with its own tolerance
// parameters back at the nominal), an effect whose fit ends back inside that box would otherwise take the part of the
// gap that its own reset had opened and the tolerances had closed (the independent device's seed 9: fpam_params, back
// at r0 x 1.0001 and eps_max -0.003, "explained" 78 % of a tensile gap the tolerances had left at 1.55 noise units, in
// most data sets). An effect fitted beyond its box keeps the share it
// closes from its base: its box's values, reached from the same base, leave that share's gap (the catalogue
// benchmark's fPAM case, r0 x 1.086 with an eps_max shifted more at higher pressure, whose whole tolerance fit ended
// in another basin, r0 at 0.97).
void measure_explained(Diagnosis& d, const GapProblem& problem, const ModelVariant& base, const Predictions& base_full,
                       const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options) {
  if (d.combination.empty()) return;
  const EffectFit& leading = d.combination.front();
  d.leading_effect = leading.name;
  const std::vector<bool> acted_on = gap_trials_acted_on(problem, d.trials, effect_spec(leading.id));
  if (std::none_of(acted_on.begin(), acted_on.end(), [](bool b) { return b; })) return;
  ModelVariant alone = base;
  apply_effect(leading.id, leading.values, alone);
  double before = problem.heldout_error(problem.heldout_sums(base_full), nullptr, &acted_on);
  const double after = problem.heldout_error(problem.heldout_sums(problem.evaluate(alone, false)), nullptr, &acted_on);
  if (leading.within_tolerances) {
    before = std::min(before, heldout_error_in_own_box(problem, base, leading.id, leading.values, after, nominal_device,
                                                       options, acted_on));
  } else if (!d.tolerance.full.empty()) {
    // Fitted from the nominal as placed, it competes with the device's scatter within the tolerances, which the whole
    // tolerance fit already closes (the independent device's seed 11: its nominal's fpam_params, r0 x 0.987 inside
    // its box and the fabric 17 % softer, 54 % from the nominal as placed, below the tolerance fit's error).
    before = std::min(before, problem.heldout_error(problem.heldout_sums(d.tolerance.full), nullptr, &acted_on));
  }
  d.explained_fraction = fraction_closed(before, after);
}

// `fit` refitted jointly with every tolerance (fit_effect_within_tolerances, from its values as fitted), and its share
// of the held-out gap they leave in the gap trials of the kinds it acts on; none where it acts on no gap trial.
std::optional<Diagnosis::BeyondTolerance> jointly_with_tolerances(const Diagnosis& d, const GapProblem& problem,
                                                                  const ModelVariant& nominal,
                                                                  const sim::DeviceDescription& nominal_device,
                                                                  const DiagnosisOptions& options,
                                                                  const EffectFit& fit) {
  const std::vector<bool> acted_on = gap_trials_acted_on(problem, d.trials, effect_spec(fit.id));
  if (std::none_of(acted_on.begin(), acted_on.end(), [](bool b) { return b; })) return std::nullopt;
  const JointFit joint = fit_effect_within_tolerances(problem, nominal, options, d.tolerance, fit.id, fit.values);
  Diagnosis::BeyondTolerance b{.id = fit.id,
                               .effect = fit.name,
                               .values = joint.values,
                               .params = describe_values(fit.id, joint.values, nominal_device),
                               .joint = true,
                               .evaluations = joint.evaluations,
                               .variant = joint.variant};
  b.train_error_within = d.tolerance.train_error_after;
  b.train_error_with_effect = problem.training_error(problem.evaluate(joint.variant, true));
  b.heldout_error_within = problem.heldout_error(problem.heldout_sums(d.tolerance.full), nullptr, &acted_on);
  b.heldout_error_with_effect =
      problem.heldout_error(problem.heldout_sums(problem.evaluate(joint.variant, false)), nullptr, &acted_on);
  b.explained_fraction = b.explained_in_acted_on = fraction_closed(b.heldout_error_within, b.heldout_error_with_effect);
  return b;
}

// Where the leading effect alone falls short of the verdict's share and the nominal was fitted within its
// tolerances: the effect fitted jointly with them (Diagnosis::leader_beyond_tolerance). Where that falls short too,
// the next single fits likewise (Diagnosis::runners_up_beyond_tolerance): ranked as fitted on a fixed base, an effect
// whose form the tolerances had partly taken (a wrist surface that is an ellipse, which the torque rig's anchors at
// their boxes' edges imitate) can trail one that soaks up the scatter (the mounts), and only fitted with them does it
// show what it closes (the independent device's seed 16, elliptical_section: the mounts 24 %, the wrap 76 %).
void measure_leader_beyond_tolerance(Diagnosis& d, const GapProblem& problem, const ModelVariant& nominal,
                                     const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options) {
  // Without a gap trial no effect acts on one, and jointly_with_tolerances fits none.
  if (d.tolerance.params.empty() || d.explained_fraction >= options.explained_fraction) return;
  if (!d.combination.empty())
    d.leader_beyond_tolerance =
        jointly_with_tolerances(d, problem, nominal, nominal_device, options, d.combination.front());
  if (d.leader_beyond_tolerance && d.leader_beyond_tolerance->explained_fraction >= options.explained_fraction) return;
  // The runners-up: the other single fits that cut the held-out error by min_gain, best first.
  std::vector<const EffectFit*> others;
  for (const EffectFit& f : d.effects) {
    const bool leads = !d.combination.empty() && f.id == d.combination.front().id;
    if (f.applicable && !leads && f.shrink_fraction >= options.min_gain) others.push_back(&f);
  }
  std::stable_sort(others.begin(), others.end(), [](const EffectFit* a, const EffectFit* b) {
    return a->heldout_error_after < b->heldout_error_after;
  });
  others.resize(std::min<std::size_t>(others.size(), static_cast<std::size_t>(options.beyond_joint_candidates)));
  for (const EffectFit* f : others) {
    if (auto b = jointly_with_tolerances(d, problem, nominal, nominal_device, options, *f))
      d.runners_up_beyond_tolerance.push_back(std::move(*b));
  }
}

// Of the effects fitted jointly with the tolerances, the one whose model fits the training part best (the selection;
// the held-out part is the report), where it is a runner-up and closes explained_fraction of the held-out gap the
// tolerances leave in the gap trials it acts on; otherwise none. A runner-up that fits no better than the leader is
// not preferred to it on its held-out share alone.
const Diagnosis::BeyondTolerance* runner_up_named(const Diagnosis& d, const DiagnosisOptions& options) {
  const Diagnosis::BeyondTolerance* best = nullptr;
  for (const auto& r : d.runners_up_beyond_tolerance) {
    if (best == nullptr || r.train_error_with_effect < best->train_error_with_effect) best = &r;
  }
  if (best == nullptr || best->explained_in_acted_on < options.explained_fraction) return nullptr;
  const auto& leader = d.leader_beyond_tolerance;
  if (leader && !(best->train_error_with_effect < leader->train_error_with_effect)) return nullptr;
  return best;
}

// Whether the second effect beyond the tolerances cuts what the first leaves by min_gain, its interval above zero.
bool second_adds(const Diagnosis& d, const DiagnosisOptions& options) {
  const auto& second = d.beyond_tolerance_second;
  if (!second || d.beyond_tolerance.empty()) return false;
  const double left = d.beyond_tolerance.front().heldout_error_with_effect;
  return left > 0.0 && fraction_closed(left, second->heldout_error_with_effect) >= options.min_gain &&
         (second->ci_low > 0.0 || !d.interval_informative);
}

// The model the diagnosis hands on (Diagnosis::corrected): beyond the tolerances, the first effect with the nominal
// within them (and the second where it adds); otherwise the greedy combination from the nominal as placed.
const ModelVariant* beyond_tolerance_model(const Diagnosis& d, const DiagnosisOptions& options) {
  if (d.beyond_tolerance.empty()) return nullptr;
  return second_adds(d, options) ? &*d.beyond_tolerance_second->variant : &*d.beyond_tolerance.front().variant;
}

// An effect fitted beyond the tolerances as an EffectFit: its held-out error before (`before`: the nominal within its
// tolerances, or the first effect's model for the second) and after, and its cut of it.
EffectFit as_effect_fit(const Diagnosis::BeyondTolerance& b, double before) {
  EffectFit f{.id = b.id, .name = b.effect, .values = b.values, .params = b.params};
  f.train_error_before = b.train_error_within;
  f.train_error_after = b.train_error_with_effect;
  f.heldout_error_before = before;
  f.heldout_error_after = b.heldout_error_with_effect;
  f.shrink_fraction = f.shrink_where_acting = fraction_closed(before, b.heldout_error_with_effect);
  f.ci_low = b.ci_low;
  f.ci_high = b.ci_high;
  f.evaluations = b.evaluations;
  return f;
}

// The trials that still have a gap (significant, and min_gap noise units) with `model`.
std::vector<bool> gaps_left(const Diagnosis& d, const GapProblem& problem, const ModelVariant& model,
                            const DiagnosisOptions& options) {
  const std::vector<TrialGap> gaps =
      nominal_trial_gaps(d.prepared, residuals_of_all(d.prepared, problem.evaluate(model, false)), options.alpha,
                         options.min_gap, options.repeat_mean_test);
  std::vector<bool> left;
  for (const TrialGap& t : gaps) left.push_back(t.gap);
  return left;
}

// With tolerances and a gap beyond them: each effect fitted on top of them, and a second where the first leaves a
// trial with a gap (beyond_tolerance.h). False when none of the effects asked for acts on these data.
bool attribute_beyond_tolerances(Diagnosis& d, const GapProblem& problem, const BaseModel& as_placed,
                                 const sim::DeviceDescription& nominal_device, const DiagnosisOptions& options) {
  const ModelVariant& nominal = as_placed.variant;
  d.beyond_tolerance = rank_beyond_tolerances(problem, as_placed, nominal_device, d.tolerance, d.trials, options);
  if (d.beyond_tolerance.empty()) return false;
  const std::vector<bool> left = gaps_left(d, problem, *d.beyond_tolerance.front().variant, options);
  if (std::any_of(left.begin(), left.end(), [](bool g) { return g; }))
    d.beyond_tolerance_second =
        second_beyond_tolerances(problem, nominal, nominal_device, d.tolerance, d.trials, d.beyond_tolerance, options);
  // The effects and the combination as the report and the command line list them.
  for (const auto& b : d.beyond_tolerance) d.effects.push_back(as_effect_fit(b, b.heldout_error_within));
  d.combination.push_back(d.effects.front());
  if (second_adds(d, options))
    d.combination.push_back(
        as_effect_fit(*d.beyond_tolerance_second, d.beyond_tolerance.front().heldout_error_with_effect));
  return true;
}

// The trials that still differ beyond their noise with the corrected model, for the reason.
std::string remaining_gaps(const Diagnosis& d) {
  std::vector<std::string> names;
  for (const auto& t : d.trials) {
    if (t.remaining_significant && t.excess_corrected > 0.0)
      names.push_back(fmt::format("{} ({:.2f} noise units)", t.experiment, t.excess_corrected));
  }
  if (names.empty()) return "no trial keeps a significant gap";
  return fmt::format("a significant gap remains in {}", fmt::join(names, ", "));
}

// What the nominal took within its tolerances, for a reason: " (the nominal within its tolerances, 30 parameters,
// moved most: a=1, b=2, ...)", the six that moved furthest into their boxes.
std::string tolerance_note(const Diagnosis& d) {
  const ToleranceFit& fit = d.tolerance;
  if (fit.params.empty()) return "";
  std::vector<std::size_t> order(fit.params.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return std::abs(fit.moved[a]) > std::abs(fit.moved[b]); });
  std::vector<std::string> values;
  for (std::size_t i = 0; i < std::min<std::size_t>(6, order.size()); ++i)
    values.push_back(fmt::format("{}={:.4g}", fit.params[order[i]].first, fit.params[order[i]].second));
  return fmt::format(" (the nominal within its tolerances, {} parameters, moved most: {})", fit.params.size(),
                     fmt::join(values, ", "));
}

// The gap trials on which the combination's second member acts where its leader cannot
// (DiagnosisOptions::second_untouched_fraction): the leader leaves the trial's held-out residual within that fraction
// of what its base left, and the second closes at least contradiction_gap noise units of it; the one it closes most
// first. Empty without a second member, or where the members' residuals per trial were not recorded
// (record_trials_closed).
std::vector<std::size_t> second_effect_candidates(const Diagnosis& d, const DiagnosisOptions& options) {
  if (d.combination.size() < 2) return {};
  const std::vector<double>& lead = d.combination[0].heldout_excess_by_trial;
  const std::vector<double>& with_second = d.combination[1].heldout_excess_by_trial;
  if (lead.size() != d.trials.size() || with_second.size() != d.trials.size()) return {};
  std::vector<std::size_t> candidates;
  for (std::size_t t = 0; t < d.trials.size(); ++t) {
    const bool untouched =
        lead[t] >= (1.0 - options.second_untouched_fraction) * d.trials[t].heldout_excess_leader_base;
    if (d.trials[t].gap && untouched && lead[t] - with_second[t] >= options.contradiction_gap) candidates.push_back(t);
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](std::size_t a, std::size_t b) { return lead[a] - with_second[a] > lead[b] - with_second[b]; });
  return candidates;
}

// What the combination's second member closes of trial `t` beyond the tolerances: of its held-out residual with the
// leader or, where lower, with the tolerances fitted to it alone (TrialGap::heldout_excess_within_alone; not measured,
// the leader's). The tolerance fit over every trial trades one trial for the others, and what the tolerances close on
// a trial by themselves holds no second effect. On the independent device's development data (seeds 41 and 42, read
// after their reports; dev_second_alone.json): an elliptical wrap named `wrap_geometry` left its tensile test 6.70
// held-out noise units off, 1.92 with `fpam_params`, which was reported beside it, and 1.16 with the tolerances fitted
// to that test alone; another, `passive_wrist`, cut ellipses the tolerances alone bring to 0.0 and 1.75 noise units
// by 3.8 and 3.7.
double second_cut_beyond_tolerances(const Diagnosis& d, std::size_t t) {
  // fmin takes the leader's where the trial was not fitted alone (NaN).
  return std::fmin(d.trials[t].heldout_excess_within_alone, d.combination[0].heldout_excess_by_trial[t]) -
         d.combination[1].heldout_excess_by_trial[t];
}

// The trial a second effect is reported on: the first candidate (second_effect_candidates, most closed with the
// leader first) where it closes at least contradiction_gap noise units beyond the tolerances.
std::optional<std::size_t> second_effect_trial(const Diagnosis& d, const DiagnosisOptions& options) {
  for (std::size_t t : second_effect_candidates(d, options)) {
    if (second_cut_beyond_tolerances(d, t) >= options.contradiction_gap) return t;
  }
  return std::nullopt;
}

// The second-effect candidates' held-out residuals with the nominal's tolerances fitted to each alone, where they
// were fitted at all (TrialGap::heldout_excess_within_alone), in order until one keeps the second (each fit is of the
// trial's own parameters, up to the tolerance fit's 200 replays of it).
void measure_candidates_alone(Diagnosis& d, ReplayEngine& engine, const ModelVariant& nominal,
                              const DiagnosisOptions& options) {
  if (d.tolerance.params.empty()) return;
  for (std::size_t t : second_effect_candidates(d, options)) {
    std::vector<PreparedTrial> alone{d.prepared[t]};
    GapProblem problem(alone, engine);
    const ToleranceFit fit = fit_within_tolerances(problem, nominal, options);
    if (!fit.variant) continue;
    const std::vector<double> excess =
        heldout_excess_by_trial(problem, problem.heldout_sums(problem.evaluate(*fit.variant, false)));
    if (!excess.empty()) d.trials[t].heldout_excess_within_alone = excess.front();
    if (second_cut_beyond_tolerances(d, t) >= options.contradiction_gap) return;
  }
}

// Reports the combination's second member beside a leader named on its own where it acts where the leader cannot
// (second_effect_trial), and says so in the reason.
void report_second_effect(Diagnosis& d, const DiagnosisOptions& options) {
  const std::optional<std::size_t> t = second_effect_trial(d, options);
  if (!t) return;
  const EffectFit& second = d.combination[1];
  d.also_effects = {second.name};
  const double alone = d.trials[*t].heldout_excess_within_alone;
  d.reason += fmt::format(
      "; {} acts besides: {} keeps {:.2f} held-out noise units with {} ({:.2f} before it{}), {:.2f} with {} too",
      second.name, d.trials[*t].experiment, d.combination[0].heldout_excess_by_trial[*t], d.leading_effect,
      d.trials[*t].heldout_excess_leader_base,
      std::isnan(alone) ? "" : fmt::format(", {:.2f} with the tolerances fitted to it alone", alone),
      second.heldout_excess_by_trial[*t], second.name);
}

// Which rule decides a verdict from the effects fitted on the nominal as placed, in this order: the combination's
// leading effect closes explained_fraction of the held-out gap alone; or of the gap beyond the tolerances fitted
// jointly with them; or a runner-up does so (runner_up_named), which the pair rule would otherwise hide behind the
// leader it does not fit as well as; or the leader closes pair_share in a combination that closes explained_fraction.
enum class AsPlacedRule { kLeader, kLeaderBeyond, kRunnerUp, kPair, kUnexplained };

AsPlacedRule as_placed_rule(const Diagnosis& d, const DiagnosisOptions& options) {
  const auto& beyond = d.leader_beyond_tolerance;
  if (!d.combination.empty() && d.explained_fraction >= options.explained_fraction) return AsPlacedRule::kLeader;
  if (beyond && beyond->explained_fraction >= options.explained_fraction) return AsPlacedRule::kLeaderBeyond;
  if (runner_up_named(d, options) != nullptr) return AsPlacedRule::kRunnerUp;
  if (d.combination.size() >= 2 && d.gap_closed() >= options.explained_fraction &&
      d.explained_fraction >= options.pair_share)
    return AsPlacedRule::kPair;
  return AsPlacedRule::kUnexplained;
}

void decide_as_placed(Diagnosis& d, const DiagnosisOptions& options) {
  const auto& beyond = d.leader_beyond_tolerance;
  switch (as_placed_rule(d, options)) {
    case AsPlacedRule::kLeader:
      d.verdict = d.leading_effect;
      d.reason = fmt::format("{} explains {:.0f} % of the held-out gap on its own ({:.0f} % with the combination); {}",
                             d.leading_effect, 100.0 * d.explained_fraction, 100.0 * d.gap_closed(), remaining_gaps(d));
      report_second_effect(d, options);
      return;
    case AsPlacedRule::kLeaderBeyond:
      d.verdict = d.leading_effect;
      d.reason = fmt::format(
          "{} explains {:.0f} % of the held-out gap beyond the nominal's tolerances when fitted with them ({:.0f} % "
          "fitted from the nominal as placed){}; {}",
          d.leading_effect, 100.0 * beyond->explained_fraction, 100.0 * d.explained_fraction, tolerance_note(d),
          remaining_gaps(d));
      report_second_effect(d, options);
      return;
    case AsPlacedRule::kRunnerUp: {
      const Diagnosis::BeyondTolerance& runner = *runner_up_named(d, options);
      d.verdict = runner.effect;
      const std::string leader =
          beyond ? fmt::format(
                       "; the leading single fit, {}, explains {:.0f} % so and fits the training part worse "
                       "({:.4g})",
                       beyond->effect, 100.0 * beyond->explained_fraction, beyond->train_error_with_effect)
                 : "";
      d.reason = fmt::format(
          "{} explains {:.0f} % of the held-out gap beyond the nominal's tolerances when fitted with them (training "
          "error {:.4g}){}{}; {}",
          runner.effect, 100.0 * runner.explained_in_acted_on, runner.train_error_with_effect, leader,
          tolerance_note(d), remaining_gaps(d));
      return;
    }
    case AsPlacedRule::kPair: {
      d.verdict = d.leading_effect;
      std::vector<std::string> others;
      for (std::size_t i = 1; i < d.combination.size(); ++i) others.push_back(d.combination[i].name);
      d.also_effects = others;
      d.reason = fmt::format(
          "{} and {} together explain {:.0f} % of the held-out gap; {} alone explains {:.0f} %, the largest share; {}",
          d.leading_effect, fmt::join(others, " and "), 100.0 * d.gap_closed(), d.leading_effect,
          100.0 * d.explained_fraction, remaining_gaps(d));
      return;
    }
    case AsPlacedRule::kUnexplained:
      d.verdict = "unexplained";
      d.reason = d.combination.empty()
                     ? "the gap is significant and no catalogue effect reduces the held-out error meaningfully"
                     : fmt::format("the gap is significant; {} explains {:.0f} % of it, the rest is unexplained; {}",
                                   d.leading_effect, 100.0 * d.explained_fraction, remaining_gaps(d));
      return;
  }
}

// The verdict beyond the tolerances: the effect that leaves the least training error (the selection), named when it
// closes explained_fraction of the held-out gap beyond the tolerances in the gap trials of the kinds it acts on, its
// bootstrap interval above zero; or, with a second effect that brings the pair to explained_fraction of the gap, when
// it closes pair_share alone. The held-out part is the report, not the selection.
void decide_beyond_tolerances(Diagnosis& d, const DiagnosisOptions& options) {
  const Diagnosis::BeyondTolerance& lead = d.beyond_tolerance.front();
  d.leading_effect = lead.effect;
  d.explained_fraction = lead.explained_in_acted_on;
  const bool lead_helps = lead.explained_fraction >= options.min_gain && (lead.ci_low > 0.0 || !d.interval_informative);
  const auto& second = d.beyond_tolerance_second;
  const bool with_second = second_adds(d, options);
  const std::string interval = d.interval_informative ? fmt::format(", 95 % interval {:.0f} to {:.0f} %",
                                                                    100.0 * lead.ci_low, 100.0 * lead.ci_high)
                                                      : "";
  if (lead_helps && lead.explained_in_acted_on >= options.explained_fraction) {
    d.verdict = lead.effect;
    if (with_second) d.also_effects = {second->effect};
    d.reason = fmt::format(
        "{} explains {:.0f} % of the held-out gap the nominal's tolerances leave, in the trials it acts on ({:.0f} % "
        "over every trial with a gap{}){}{}; {}",
        lead.effect, 100.0 * lead.explained_in_acted_on, 100.0 * lead.explained_fraction, interval,
        with_second ? fmt::format("; with {} {:.0f} %", second->effect, 100.0 * second->explained_fraction) : "",
        tolerance_note(d), remaining_gaps(d));
  } else if (lead_helps && with_second && lead.explained_in_acted_on >= options.pair_share &&
             second->explained_fraction >= options.explained_fraction) {
    d.verdict = lead.effect;
    d.also_effects = {second->effect};
    d.reason = fmt::format(
        "{} and {} together explain {:.0f} % of the held-out gap the nominal's tolerances leave; {} alone explains "
        "{:.0f} % in the trials it acts on, the larger share{}; {}",
        lead.effect, second->effect, 100.0 * second->explained_fraction, lead.effect,
        100.0 * lead.explained_in_acted_on, tolerance_note(d), remaining_gaps(d));
  } else {
    d.verdict = "unexplained";
    d.reason = fmt::format(
        "the gap beyond the nominal's tolerances is significant; {}, the best fit, explains {:.0f} % of it in the "
        "trials it acts on ({:.0f} % over every trial with a gap{}), the rest is unexplained{}; {}",
        lead.effect, 100.0 * lead.explained_in_acted_on, 100.0 * lead.explained_fraction, interval, tolerance_note(d),
        remaining_gaps(d));
  }
}

// A trial's excess with the model the corrected one was built on: the nominal within its tolerances where the
// single fits' leader, whose base the combination starts from, was fitted on them (its own base), or where the
// effects were ranked beyond them; the nominal as placed otherwise. The whole tolerance fit's excess stands for the
// own base's, which differs from it only in the leader's own tolerance parameters (not kept apart; an approximation
// where those move the trial, as an fPAM's r0 moves a range of motion).
double excess_of_base(const Diagnosis& d, const TrialGap& t) {
  const bool on_tolerances =
      !d.tolerance.params.empty() &&
      (!d.beyond_tolerance.empty() || (!d.effects.empty() && d.effects.front().within_tolerances));
  return on_tolerances ? t.excess_within_tolerance : t.excess_nominal;
}

// What says that the device changed during the session, which no constant property of it explains, whatever the
// verdict as fitted: the gap drifts between the repetitions of a condition (drift.h), or a sweep's repeats disagree
// at one setting far more than at the others (setting_change.h).
std::vector<std::string> device_changes(const Diagnosis& d) {
  std::vector<std::string> why;
  for (const TrialDrift& t : d.drift) {
    if (!t.significant) continue;
    why.push_back(fmt::format(
        "the gap drifts over the session, which no constant property of the device explains (a fabric that "
        "creeps, a sensor that warms up, a mount that slips): {}: repetition {} reads {:+.2f} noise units from "
        "repetition {} over {} conditions (t = {:.1f})",
        t.experiment, t.last_repetition, t.shift, t.first_repetition, t.conditions, t.t));
  }
  for (const SettingChange& c : d.setting_changes) {
    if (!c.significant) continue;
    why.push_back(fmt::format(
        "the device changed during one setting, which no constant property of it explains (a strap that slips, a "
        "band re-seated, a plate knocked): {}: the {} at {:.1f} deg, where repetitions {} and {} differ by amounts "
        "that scatter {:.3g} {} ({:.2f} noise units) from pressure to pressure, {:.0f} times the variance at the "
        "median of the other {} settings",
        c.experiment, c.muscle, c.angle_deg, c.first_repetition, c.last_repetition, c.spread, c.unit,
        c.spread_noise_units, c.ratio, c.settings - 1));
  }
  return why;
}

// Neither a named effect nor the nominal is the account where the device changed during the session
// (device_changes), whatever the verdict as fitted. A named effect is not the cause either where the data contradict
// it: the corrected model misses a trial the nominal matched (DiagnosisOptions::contradiction_gap), both as placed and
// as the base the effect was added to. A miss the base already had is the tolerance fit's trade between trials, not
// the effect's (the independent device's seed 12: a regulator's dead time and rate limit, 78 % of the pressures' gap,
// was added to a tolerance fit that had moved the ellipses' angle trials from 0.0-0.6 noise units as placed to
// 2.8-3.9, for the range of motion; the corrected model missed them by as much, and a regulator does not move a
// trajectory replayed from its measured pressures).
void unexplained_where_contradicted(Diagnosis& d, const DiagnosisOptions& options) {
  std::vector<std::string> why = device_changes(d);
  const bool named = d.verdict != "none" && d.verdict != "unexplained";
  for (const TrialGap& t : d.trials) {
    if (named && t.excess_nominal < options.min_gap && excess_of_base(d, t) < options.min_gap &&
        t.remaining_significant && t.excess_corrected >= options.contradiction_gap)
      why.push_back(
          fmt::format("{} contradicts {}: the nominal matched it ({:.2f} noise units), the corrected model "
                      "misses it by {:.2f}",
                      d.verdict, t.experiment, t.excess_nominal, t.excess_corrected));
  }
  if (why.empty()) return;
  // Already `unexplained` (a change also keeps none_without_evidence from reading a small gap as the model's
  // inexactness): the change leads the reason all the same.
  d.reason = fmt::format("{}; {}{}", fmt::join(why, "; "), d.verdict == "unexplained" ? "" : "as fitted, ", d.reason);
  d.verdict = "unexplained";
  d.also_effects.clear();
}

// A tolerance the nominal's fit pins at an edge of its box, where the effect owning it, fitted alone, takes the same
// catalogue parameter beyond that edge and closes at least pair_share of the held-out error of its base where it acts
// (EffectFit::shrink_where_acting): the device lies beyond its tolerance there, and the tolerances absorbed the effect
// only by spending that box whole. Any such effect, not only the combination's leader (until commit 084e178, with
// explained_fraction): the tolerances share the effect out, and the whole fPAM, refitted as placed, can out-fit the
// mounts alone on a strap that stiffens (seed 1005: the fPAM led with 75 %, the mounts alone took the series stiffness
// to 12.6 N/cm^2 past the edge's 21.1 and closed 36 %). A nominal within its tolerances fits at the edges too (its
// regulator's time constant: 26 of the 27 data sets of seed 43), but the effect owning such an edge closes little
// alone: at most 0.05 of the error on the nominals of seeds 41-43, 49, 50 and calibration seeds 1005-1024 (the relaxed
// wrist's damping; the regulator's 0.01), against 0.34-0.84 where a strap stiffened or a glove slid (docs/diagnosis.md,
// "Tolerances"). The effect is read in its base form: an exponent, a preload or a shaped share changes what its series
// stiffness means, which the tolerance's box does not. Where its extensions were kept, the base form's fit they
// replaced is read (EffectFit::base_form; until then such a fit was passed over). Of several, the one closing most.
struct PinnedBeyond {
  const EffectFit* effect = nullptr;
  std::string parameter;         // "mount_stretch.K_series_n_per_cm2"
  double within = 0.0;           // the tolerance fit's value, at the edge
  double effect_value = 0.0;     // the effect's own, beyond it
  double shrink_fraction = 0.0;  // the fit read's share where it acts (EffectFit::shrink_where_acting)
  bool base_form = false;        // the fit read is the base form an extension replaced
};
std::optional<PinnedBeyond> beyond_pinned_edge(const ToleranceFit& fit, const EffectFit& effect) {
  if (effect.extended && !effect.base_form) return std::nullopt;  // an extended fit whose base form was not kept
  const auto& params = effect.extended ? effect.base_form->params : effect.params;
  const double shrink = effect.extended ? effect.base_form->shrink_where_acting : effect.shrink_where_acting;
  for (std::size_t k = 0; k < fit.params.size(); ++k) {
    const auto& [name, within] = fit.params[k];
    const bool pinned = std::find(fit.at_bound.begin(), fit.at_bound.end(), name) != fit.at_bound.end();
    if (!pinned || !name.starts_with(effect.name + ".")) continue;
    if (k >= fit.boxes.size()) throw std::logic_error("a tolerance fit without the boxes of its parameters");
    const std::string own = name.substr(effect.name.size() + 1);
    const auto value = std::find_if(params.begin(), params.end(), [&](const auto& p) { return p.first == own; });
    if (value == params.end()) continue;
    const auto [low, high] = fit.boxes[k];
    const bool at_low = std::abs(within - low) < std::abs(within - high);
    if (at_low ? value->second < low : value->second > high)
      return PinnedBeyond{.effect = &effect,
                          .parameter = name,
                          .within = within,
                          .effect_value = value->second,
                          .shrink_fraction = shrink,
                          .base_form = effect.extended};
  }
  return std::nullopt;
}
std::optional<PinnedBeyond> effect_beyond_pinned_tolerance(const Diagnosis& d, const DiagnosisOptions& options) {
  std::optional<PinnedBeyond> best;
  for (const EffectFit& e : d.effects) {
    if (!e.applicable) continue;
    if (auto pinned = beyond_pinned_edge(d.tolerance, e); pinned && pinned->shrink_fraction >= options.pair_share &&
                                                          (!best || pinned->shrink_fraction > best->shrink_fraction))
      best = std::move(pinned);
  }
  return best;
}

// The verdict where a pinned tolerance names its effect (effect_beyond_pinned_tolerance); `found` says what the
// tolerances left.
void name_pinned_effect(Diagnosis& d, const PinnedBeyond& pinned, const std::string& found) {
  d.verdict = pinned.effect->name;
  d.reason = fmt::format(
      "the nominal within its tolerances fits the trials only at an edge of a tolerance, {}={:.4g}, which {} fitted "
      "alone{} takes further ({:.4g}) while closing {:.0f} % of its base's held-out error where it acts: the device "
      "lies beyond its tolerance there{}; {}",
      pinned.parameter, pinned.within, pinned.effect->name, pinned.base_form ? " in its base form" : "",
      pinned.effect_value, 100.0 * pinned.shrink_fraction, tolerance_note(d), found);
}

// Where the verdict names the combination's leader but the tolerances absorbed another member by spending its box
// whole (effect_beyond_pinned_tolerance), which of the two is larger is read from their single fits: each one's share
// of its own base's held-out error, and the absorbed effect's base has that box back at the nominal. A rough
// measure (two fractions of different bases, the device's scatter within the box counted with the effect, which one
// data set cannot separate), but the gap the tolerances leave shows the absorbed effect hardly at all. Where the
// absorbed one's share is the larger it is named and the leader reported beside it; both are in the corrected model
// (the combination), which is why only a member counts. The independent device's seed 54, a sliding glove (12.5 noise
// units in the torque sweep) beside a second-order regulator (5.0 in the pressures): the tolerances pinned the
// mounts' series stiffness at 21.12 N/cm^2, the mounts alone took it to 21.0 and closed 73 % of their base's error,
// the regulator 28 % of its, and the regulator had been named. Both shares are read where each effect acts, and the
// absorbed effect in its base form, as effect_beyond_pinned_tolerance reads them.
void name_absorbed_larger(Diagnosis& d, const DiagnosisOptions& options) {
  if (d.combination.empty() || d.verdict != d.combination.front().name || !d.beyond_tolerance.empty()) return;
  const auto pinned = effect_beyond_pinned_tolerance(d, options);
  const auto named =
      std::find_if(d.effects.begin(), d.effects.end(), [&](const EffectFit& e) { return e.name == d.verdict; });
  const auto member = [&](const std::string& name) {
    return std::any_of(d.combination.begin(), d.combination.end(), [&](const EffectFit& e) { return e.name == name; });
  };
  if (!pinned || named == d.effects.end() || !member(pinned->effect->name) ||
      !(pinned->shrink_fraction > named->shrink_where_acting))
    return;
  std::vector<std::string> also = {d.verdict};
  for (const std::string& e : d.also_effects)
    if (e != pinned->effect->name) also.push_back(e);
  d.reason = fmt::format(
      "{} is the larger: the tolerances absorbed it at an edge, {}={:.4g}, which it fitted alone{} takes further "
      "({:.4g}) while closing {:.0f} % of its base's held-out error where it acts, against {:.0f} % for {} alone; as "
      "fitted, {}",
      pinned->effect->name, pinned->parameter, pinned->within, pinned->base_form ? " in its base form" : "",
      pinned->effect_value, 100.0 * pinned->shrink_fraction, 100.0 * named->shrink_where_acting, d.verdict, d.reason);
  d.verdict = pinned->effect->name;
  d.also_effects = std::move(also);
}

// An effect outside the catalogue is reported (`unexplained`) only on a gap that evidences one: a device that changed
// during the session (device_changes), or some gap trial left at least contradiction_gap noise units off by the nominal
// within its tolerances, the level at which a trial's residual contradicts a named effect
// (unexplained_where_contradicted). A smaller residual that no catalogue effect closes is the model's own inexactness,
// and the verdict is `none`, the residual named (the independent device's nominal, seeds 9 and 10: its tensile test
// 1.0-1.3 noise units off over 1689 points within the tolerances, which no effect closed).
void none_without_evidence(Diagnosis& d, const DiagnosisOptions& options) {
  if (d.verdict != "unexplained") return;
  // A device that changed during the session evidences an effect whatever the gap's size.
  if (!device_changes(d).empty()) return;
  const bool within = !d.tolerance.params.empty();
  const TrialGap* largest = nullptr;
  double largest_left = 0.0;
  for (const TrialGap& t : d.trials) {
    double left = within ? t.excess_within_tolerance : t.excess_nominal;
    // With the tasks tested whole, a repetition evidences no more than the error its task's repetitions share.
    const double shared = within ? t.repeat_excess_within_tolerance : t.repeat_excess;
    if (options.repeat_mean_test && std::isfinite(shared)) left = std::min(left, shared);
    if (t.gap && left >= largest_left) largest = &t, largest_left = left;
  }
  if (largest == nullptr || largest_left >= options.contradiction_gap) return;
  if (const auto pinned = effect_beyond_pinned_tolerance(d, options)) {
    return name_pinned_effect(d, *pinned,
                              fmt::format("the largest gap left within them, {:.2f} noise units ({}), is below the {} "
                                          "that evidence an effect outside the catalogue",
                                          largest_left, largest->experiment, options.contradiction_gap));
  }
  d.reason = fmt::format(
      "no effect beyond the model's own inexactness: the largest gap{}, {:.2f} noise units ({}), is below the {} that "
      "evidence an effect outside the catalogue, and no catalogue effect explains it ({})",
      within ? " left within the tolerances" : "", largest_left, largest->experiment, options.contradiction_gap,
      d.reason);
  d.verdict = "none";
}

// The nominal within its tolerances leaves no gap: `none`, unless it did so only by pinning a tolerance that an effect
// takes further (effect_beyond_pinned_tolerance).
void decide_within_tolerances(Diagnosis& d, const DiagnosisOptions& options, const TrialGap& largest) {
  const std::string found = fmt::format("the largest gap as placed, {:.2f} noise units ({}), is {:.2f} within them",
                                        largest.excess_nominal, largest.experiment, largest.excess_within_tolerance);
  if (const auto pinned = effect_beyond_pinned_tolerance(d, options)) return name_pinned_effect(d, *pinned, found);
  d.verdict = "none";
  d.reason = fmt::format("the nominal within its tolerances explains every trial that differs from it as placed{}: {}",
                         tolerance_note(d), found);
}

void decide_verdict(Diagnosis& d, const DiagnosisOptions& options) {
  const bool any_significant =
      std::any_of(d.trials.begin(), d.trials.end(), [](const TrialGap& t) { return t.significant; });
  const bool any_gap = std::any_of(d.trials.begin(), d.trials.end(), [](const TrialGap& t) { return t.gap; });
  const auto largest = std::max_element(d.trials.begin(), d.trials.end(), [](const TrialGap& a, const TrialGap& b) {
    return a.excess_nominal < b.excess_nominal;
  });
  if (!any_significant) {
    d.verdict = "none";
    d.reason = fmt::format(
        "no trial differs from the nominal model beyond its repeat-to-repeat noise (F test, alpha {} over {} trials)",
        options.alpha, d.prepared.size());
  } else if (!any_gap && !d.tolerance.params.empty()) {
    decide_within_tolerances(d, options, *largest);
  } else if (!any_gap) {
    d.verdict = "none";
    d.reason = fmt::format(
        "the largest systematic residual of a trial is {:.2f} of its noise ({}; below {}): detectable in this much "
        "data, but within the noise of a measurement",
        largest->excess_nominal, largest->experiment, options.min_gap);
  } else if (!d.beyond_tolerance.empty()) {
    decide_beyond_tolerances(d, options);
  } else {
    decide_as_placed(d, options);
  }
  name_absorbed_larger(d, options);
  none_without_evidence(d, options);
}

// The evidence that the device changed during the session (device_changes): the corrected model's residuals drifting
// between repetitions, and a sweep's repeats disagreeing at one setting on the nominal's residuals. The nominal's, not
// the corrected model's: a fitted hysteresis starts the log on one branch and turns over the first setting, a
// transient of the model's own that reads as a change there (a sweep scaled 1 -+ h by side,
// SweepReachedFromBothSidesShowsHysteresis: 41 times the other settings' variance); the nominal as placed has no
// state, so both repetitions of a condition replay alike and the differences are the readings' own.
void test_for_device_changes(Diagnosis& d) {
  d.drift = drift_across_repetitions(d.prepared, d.corrected_predictions);
  d.setting_changes = change_at_one_setting(d.prepared, d.nominal_predictions);
}

// What the nominal leaves, before any effect: its predictions of every trial and of the training part, and (with more
// than one job) each effect's search from it, run beside the tolerance fit.
struct NominalStage {
  Predictions full, training;
  std::optional<std::vector<EffectSearch>> as_placed_searches;
};

// The first stage, with the trials prepared (d.prepared) and the nominal routed (apply_routing): replay the nominal as
// placed, localise, test each trial's gap, and fit the nominal within its tolerances where some trial has one.
// `search_beside`: start the effects' searches from the nominal as placed beside the tolerance fit (a routing still to
// be chosen would waste them).
NominalStage replay_nominal(Diagnosis& d, ReplayEngine& engine, const ModelVariant& nominal,
                            const DiagnosisOptions& options, bool search_beside) {
  GapProblem problem(d.prepared, engine);

  // Replay with the nominal model as placed; localise; test each trial's gap.
  NominalStage stage{.full = problem.evaluate(nominal, false), .training = problem.evaluate(nominal, true)};
  d.nominal_predictions = stage.full;
  const std::vector<std::vector<double>> residuals = residuals_of_all(d.prepared, stage.full);
  d.localization = localize(d.prepared, residuals, nominal.device, options.alpha);
  d.heldout_nominal = problem.heldout_error(problem.heldout_sums(stage.full));
  d.trials = nominal_trial_gaps(d.prepared, residuals, options.alpha, options.min_gap, options.repeat_mean_test);
  const BaseModel reference{.variant = nominal, .training = stage.training, .full = stage.full};
  // The effects' searches from the nominal as placed read neither the tolerance fit nor the scored trials: with more
  // than one job they run while the tolerances are fitted (each on `jobs` threads), whose Levenberg-Marquardt steps,
  // one replay each, leave a thread idle.
  std::future<std::vector<EffectSearch>> as_placed_searches;
  if (search_beside && options.jobs > 1 && options.effect_base != EffectBase::kWithinTolerances &&
      !options.rank_beyond_tolerances) {
    as_placed_searches = std::async(std::launch::async, [&] {
      return search_from_base(
          problem, requested_effects(options), [&](EffectId) { return reference; }, options);
    });
  }
  check_within_tolerances(d, problem, nominal, options);
  if (as_placed_searches.valid()) stage.as_placed_searches = as_placed_searches.get();
  return stage;
}

// The second stage: attribute the gap the first left to the catalogue's effects, measure the corrected model, decide.
void attribute_gap(Diagnosis& d, ReplayEngine& engine, const ModelVariant& nominal, NominalStage stage,
                   const DiagnosisOptions& options) {
  const sim::DeviceDescription& nominal_device = nominal.device;
  GapProblem problem(d.prepared, engine);
  const Predictions& nominal_full = stage.full;
  const BaseModel reference{.variant = nominal, .training = stage.training, .full = stage.full};
  std::optional<std::vector<EffectSearch>> searched_as_placed = std::move(stage.as_placed_searches);

  // Attribute, scored over the trials with a gap beyond the tolerances (a gap the nominal explains within them is no
  // effect's to close): beyond the tolerances where they were fitted and leave a gap; otherwise each effect alone
  // from the nominal as placed, then the greedy combination. Measure the corrected model; decide.
  std::vector<bool> gap_trials;
  for (const auto& t : d.trials) gap_trials.push_back(t.gap);
  const bool any_gap = std::any_of(gap_trials.begin(), gap_trials.end(), [](bool g) { return g; });
  if (any_gap) problem.set_scored(gap_trials);
  d.interval_informative = interval_informative(problem);
  if (any_gap && !d.tolerance.params.empty() && options.rank_beyond_tolerances &&
      attribute_beyond_tolerances(d, problem, reference, nominal_device, options)) {
    d.corrected.emplace(*beyond_tolerance_model(d, options));
    d.corrected_predictions = problem.evaluate(*d.corrected, false);
  } else {
    // The bases the effects are fitted from (EffectBase): the nominal as placed, within its tolerances (where they
    // were fitted), or both; the combination grows from its leader's.
    EffectBases bases{.as_placed = reference, .as_placed_too = options.effect_base != EffectBase::kWithinTolerances};
    bases.as_placed_searches = std::move(searched_as_placed);
    if (options.effect_base != EffectBase::kAsPlaced && any_gap)
      bases.make_own = [&] { return own_bases_within_tolerances(d, problem, nominal, options); };
    d.effects = fit_each_effect(problem, bases, nominal_device, options);
    measure_shares_where_acting(d.effects, problem, d.trials, bases);
    const BaseModel base = d.effects.empty() ? reference : bases.of(d.effects.front());  // the leader's
    WithoutOwnTolerances without_own;
    if (!d.effects.empty() && d.effects.front().within_tolerances) {
      without_own = [&](std::span<const EffectId> ids) {
        return within_tolerances_without(problem, nominal, options, d.tolerance, ids);
      };
    }
    Combination combination = combine_greedily(problem, d.effects, base, without_own, nominal, options);
    if (options.joint_refit_evaluations > 0 && !combination.effects.empty()) {
      combination.model = refit_jointly(problem, combination.effects, nominal, options);
      combination.full = problem.evaluate(combination.model, false);
    }
    d.combination = std::move(combination.effects);
    d.corrected.emplace(std::move(combination.model));
    d.corrected_predictions = std::move(combination.full);
    measure_explained(d, problem, base.variant, base.full, nominal_device, options);
    record_trials_closed(d, problem, base.full);
    measure_candidates_alone(d, engine, nominal, options);
    measure_leader_beyond_tolerance(d, problem, nominal, nominal_device, options);
    // A runner-up the verdict names is the correction: the combination does not hold it.
    if (as_placed_rule(d, options) == AsPlacedRule::kRunnerUp) {
      d.corrected = runner_up_named(d, options)->variant;
      d.corrected_predictions = problem.evaluate(*d.corrected, false);
    }
  }
  // What the corrected model leaves is tested trial by trial at Bonferroni's alpha / trials (a remaining gap
  // contradicts a named effect, unexplained_where_contradicted); the gap tests above are Holm's.
  const double trial_alpha = options.alpha / static_cast<double>(problem.size());
  measure_correction(d, problem, nominal_full, d.corrected_predictions, trial_alpha);
  test_for_device_changes(d);
  redecide(d, options);
}

// A diagnosis with its trials prepared and its nominal routed, before its first stage (replay_nominal).
struct Routed {
  Diagnosis d;
  ModelVariant nominal;
};

// `routing`, or (nullopt) the routings to try (routings_to_try) into `to_try`, the first of them applied.
Routed prepare_routed(RealData data, const sim::DeviceDescription& device_as_filed, ReplayEngine& engine,
                      const DiagnosisOptions& options, std::optional<sim::Routing> routing,
                      std::vector<sim::Routing>* to_try) {
  Routed r{.nominal = {.device = device_as_filed}};  // as placed: the effects are fitted from it
  r.d.data = std::move(data);
  r.d.problems = r.d.data.problems;
  prepare_trials(r.d, engine, r.nominal);
  if (!routing) {
    *to_try = routings_to_try(r.d, engine, r.nominal, options);
    routing = to_try->front();
  }
  apply_routing(r.d, engine, r.nominal, *routing);
  return r;
}

// The whole diagnosis with `routing` (or the first of those to try), with its nominal as placed and routed.
Routed diagnose_with_routing(RealData data, const sim::DeviceDescription& device_as_filed, ReplayEngine& engine,
                             const DiagnosisOptions& options, std::optional<sim::Routing> routing,
                             std::vector<sim::Routing>* to_try) {
  Routed r = prepare_routed(std::move(data), device_as_filed, engine, options, routing, to_try);
  attribute_gap(r.d, engine, r.nominal, replay_nominal(r.d, engine, r.nominal, options, true), options);
  return r;
}

// The held-out error, on `problem`'s trials and weights, of `d`'s nominal within its tolerances, or `as_placed` (routed
// as `d`) where none were fitted: models fitted on the training part alone.
double nominal_heldout_error(const GapProblem& problem, const Diagnosis& d, const ModelVariant& as_placed) {
  const ModelVariant& model = d.tolerance.variant ? *d.tolerance.variant : as_placed;
  return problem.heldout_error(problem.heldout_sums(problem.evaluate(model, false)));
}

// The lower held-out error, on `problem`'s trials and weights, of the models `d` ended with: its corrected model and
// its nominal within the tolerances, whose error `nominal_error` is (nominal_heldout_error; a `none` leaves it as its
// account of the data, while its corrected model may be the nominal as placed). Infinite without either.
double best_heldout_error(const GapProblem& problem, const Diagnosis& d, double nominal_error) {
  double best = d.tolerance.variant ? nominal_error : std::numeric_limits<double>::infinity();
  if (d.corrected)
    best = std::min(best, problem.heldout_error(problem.heldout_sums(problem.evaluate(*d.corrected, false))));
  return best;
}

// DiagnosisOptions::routing_by kNominalWithinTolerances: where the routing is open, each routing's first stage
// (replay_nominal: its nominal within its tolerances, fitted on the training part), and only the one whose nominal
// predicts the held-out part of the trials the routing changes better goes on to the effects (weighed on the first's
// trials and noise). The held-out part chose nothing either compares; half the effects' searches of kBestModel.
Diagnosis diagnose_routed_by_nominal(RealData data, const sim::DeviceDescription& device_as_filed, ReplayEngine& engine,
                                     const DiagnosisOptions& options) {
  std::vector<sim::Routing> to_try;
  RealData second_data = data;
  Routed first = prepare_routed(std::move(data), device_as_filed, engine, options, std::nullopt, &to_try);
  const bool open = to_try.size() > 1;
  NominalStage first_stage = replay_nominal(first.d, engine, first.nominal, options, !open);
  if (!open) {
    attribute_gap(first.d, engine, first.nominal, std::move(first_stage), options);
    return std::move(first.d);
  }
  Routed second = prepare_routed(std::move(second_data), device_as_filed, engine, options, to_try[1], nullptr);
  NominalStage second_stage = replay_nominal(second.d, engine, second.nominal, options, false);
  std::vector<PreparedTrial> compared = trials_the_routing_changes(first.d.prepared);
  GapProblem problem(compared, engine);
  const double error_first = nominal_heldout_error(problem, first.d, first.nominal);
  const double error_second = nominal_heldout_error(problem, second.d, second.nominal);
  const bool second_better = error_second < error_first;
  Routed& kept = second_better ? second : first;
  attribute_gap(kept.d, engine, kept.nominal, std::move(second_better ? second_stage : first_stage), options);
  kept.d.routing_training_error = first.d.routing_training_error;
  kept.d.routing_heldout_error_nominal = {{first.d.routing, error_first}, {second.d.routing, error_second}};
  return std::move(kept.d);
}

}  // namespace

Diagnosis diagnose(RealData data, const sim::DeviceDescription& device_as_filed, ReplayEngine& engine,
                   const DiagnosisOptions& options) {
  if (options.routing_by == RoutingBy::kNominalWithinTolerances)
    return diagnose_routed_by_nominal(std::move(data), device_as_filed, engine, options);
  std::vector<sim::Routing> to_try;
  RealData second_data = data;  // a second routing, where the first leaves the choice open, diagnoses it afresh
  Routed first = diagnose_with_routing(std::move(data), device_as_filed, engine, options, std::nullopt, &to_try);
  if (to_try.size() < 2) return std::move(first.d);
  Routed second = diagnose_with_routing(std::move(second_data), device_as_filed, engine, options, to_try[1], nullptr);
  // RoutingBy::kBestModel. Each routing's diagnosis fitted its own tolerances and effects; the one whose models predict
  // the held-out part better is kept, both weighed on the first's trials and noise, over the trials the routing changes
  // only (over every trial, the torque sweeps and tensile tests, which both replay alike, let whichever search happened
  // to fit them better decide: the independent benchmark's seed 8, 27 data sets of a device routed planar, spatial kept
  // in 5). Held out rather than trained on: a wrong routing's corrected model gathers effects until it fits the
  // training part as well as the right one's nominal within its tolerances (the independent device's nominal, seed 14:
  // 0.840 spatial with a mount stretch on top, 0.848 planar; held out 1.78 against 0.31, and the spatial one had read
  // `unexplained`). Not wholly independent of the fits: the held-out part also decided which effects each run kept.
  // Both within the noise (0 and 0) keep the first, the routing that fitted better as placed.
  std::vector<PreparedTrial> compared = trials_the_routing_changes(first.d.prepared);
  GapProblem problem(compared, engine);
  // Each one's nominal with its rigs (as placed, where no tolerance was fitted): reported beside, and replayed once.
  const double nominal_first = nominal_heldout_error(problem, first.d, first.nominal);
  const double nominal_second = nominal_heldout_error(problem, second.d, second.nominal);
  const double best_first = best_heldout_error(problem, first.d, nominal_first);
  const double best_second = best_heldout_error(problem, second.d, nominal_second);
  Diagnosis& kept = best_second < best_first ? second.d : first.d;
  kept.routing_training_error = first.d.routing_training_error;
  kept.routing_heldout_error = {{first.d.routing, best_first}, {second.d.routing, best_second}};
  kept.routing_heldout_error_nominal = {{first.d.routing, nominal_first}, {second.d.routing, nominal_second}};
  return std::move(kept);
}

void redecide(Diagnosis& d, const DiagnosisOptions& options) {
  d.also_effects.clear();
  decide_verdict(d, options);
  unexplained_where_contradicted(d, options);
}

}  // namespace softwrist::diagnosis
