#include "diagnosis/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <functional>
#include <stdexcept>

#include <fmt/format.h>
#include <nlopt.hpp>

#include "common/parallel_for.h"
#include "physics/errors.h"

namespace softwrist::diagnosis {
namespace {

// A failed replay or an unphysical parameter makes the objective this large, so the search turns away.
constexpr double kInfeasible = 1e12;

// Per trial and split unit: sum of (r/sigma)^2 and count, over held-out measurements.
struct UnitSums {
  std::vector<std::vector<std::pair<double, int>>> per_trial;  // [trial][unit]
};

struct Evaluation {
  std::vector<std::vector<double>> predictions;  // [trial][point]
};

class Problem {
 public:
  Problem(std::vector<PreparedTrial>& trials, ReplayEngine& engine) : trials_(trials), engine_(engine) {}

  Evaluation evaluate(const ModelVariant& variant, bool training_only, const EffectSpec* only_changed = nullptr) const {
    Evaluation e;
    e.predictions.resize(trials_.size());
    for (std::size_t t = 0; t < trials_.size(); ++t) {
      // A trial the effect does not act on keeps the base model's predictions (filled by the caller).
      if (only_changed != nullptr && !only_changed->acts_on_kind(trials_[t].trial->kind)) continue;
      e.predictions[t] = engine_.predict(trials_[t], variant, training_only);
    }
    return e;
  }

  // The fit's objective: mean over kinds of the mean over trials of mean (r/sigma)^2 over training measurements.
  double training_error(const std::vector<std::vector<double>>& predictions) const {
    return mean_over_kinds(nullptr, [&](std::size_t t) {
      const PreparedTrial& trial = trials_[t];
      double sum = 0.0;
      int n = 0;
      for (std::size_t i = 0; i < trial.points.size(); ++i) {
        if (trial.points[i].heldout) continue;
        sum += std::pow((trial.points[i].measured - predictions[t][i]) / trial.noise, 2);
        ++n;
      }
      return n > 0 ? sum / n : 0.0;
    });
  }

  UnitSums heldout_sums(const std::vector<std::vector<double>>& predictions) const {
    UnitSums sums;
    for (std::size_t t = 0; t < trials_.size(); ++t) {
      const PreparedTrial& trial = trials_[t];
      int units = 0;
      for (const auto& p : trial.points) units = std::max(units, p.unit + 1);
      std::vector<std::pair<double, int>> per_unit(static_cast<std::size_t>(units));
      for (std::size_t i = 0; i < trial.points.size(); ++i) {
        if (!trial.points[i].heldout) continue;
        auto& u = per_unit[static_cast<std::size_t>(trial.points[i].unit)];
        u.first += std::pow((trial.points[i].measured - predictions[t][i]) / trial.noise, 2);
        ++u.second;
      }
      sums.per_trial.push_back(std::move(per_unit));
    }
    return sums;
  }

  // The held-out error of unit sums, with each unit counted `weights[t][u]` times (1 for the data as it is); with
  // `only`, over the trials it marks.
  double heldout_error(const UnitSums& sums, const std::vector<std::vector<int>>* weights = nullptr,
                       const std::vector<bool>* only = nullptr) const {
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

  // Units with held-out measurements, per trial, for the bootstrap.
  std::vector<std::vector<std::size_t>> heldout_units() const {
    std::vector<std::vector<std::size_t>> units(trials_.size());
    for (std::size_t t = 0; t < trials_.size(); ++t) {
      std::set<std::size_t> seen;
      for (const auto& p : trials_[t].points) {
        if (p.heldout) seen.insert(static_cast<std::size_t>(p.unit));
      }
      units[t].assign(seen.begin(), seen.end());
    }
    return units;
  }

  std::size_t size() const { return trials_.size(); }
  const std::vector<PreparedTrial>& trials() const { return trials_; }
  ReplayEngine& engine() const { return engine_; }

 private:
  double mean_over_kinds(const std::vector<bool>* only, const std::function<double(std::size_t)>& per_trial) const {
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

  std::vector<PreparedTrial>& trials_;
  ReplayEngine& engine_;
};

// Parameters <-> the unit cube the search runs in (log space where the spec says so).
double to_unit(const ParameterSpec& p, double v) {
  return p.log_scale ? std::log(v / p.lower) / std::log(p.upper / p.lower) : (v - p.lower) / (p.upper - p.lower);
}
double from_unit(const ParameterSpec& p, double u) {
  u = std::clamp(u, 0.0, 1.0);
  return p.log_scale ? p.lower * std::pow(p.upper / p.lower, u) : p.lower + u * (p.upper - p.lower);
}

// The bootstrap's 95 % interval of the shrink fraction, resampling each trial's held-out units with replacement;
// both models see the same resample. Resamples with no gap left to shrink are left out.
std::pair<double, double> bootstrap_interval(const Problem& problem, const UnitSums& before, const UnitSums& after,
                                             int resamples, std::uint64_t seed) {
  const auto units = problem.heldout_units();
  std::mt19937_64 rng(seed);
  std::vector<double> shrinks;
  std::vector<std::vector<int>> weights(problem.size());
  for (int b = 0; b < resamples; ++b) {
    for (std::size_t t = 0; t < problem.size(); ++t) {
      weights[t].assign(before.per_trial[t].size(), 0);
      if (units[t].empty()) continue;
      std::uniform_int_distribution<std::size_t> pick(0, units[t].size() - 1);
      for (std::size_t k = 0; k < units[t].size(); ++k) ++weights[t][units[t][pick(rng)]];
    }
    const double e0 = problem.heldout_error(before, &weights), e1 = problem.heldout_error(after, &weights);
    // A resample without any gap (all its units where the model was already right) says nothing of the shrink.
    if (e0 > 0.0) shrinks.push_back((e0 - e1) / e0);
  }
  if (shrinks.empty()) return {0.0, 0.0};
  std::sort(shrinks.begin(), shrinks.end());
  const auto at = [&](double q) { return shrinks[static_cast<std::size_t>(q * static_cast<double>(shrinks.size() - 1))]; };
  return {at(0.025), at(0.975)};
}

// Fits effect `id` on top of `base` (whose predictions are given) and measures it on the held-out part.
EffectFit fit_effect(const Problem& problem, EffectId id, const ModelVariant& base,
                     const std::vector<std::vector<double>>& base_training, const std::vector<std::vector<double>>& base_full,
                     const sim::DeviceDescription& nominal, const DiagnosisOptions& options, std::uint64_t seed) {
  const EffectSpec& spec = effect_spec(id);
  EffectFit fit{.id = id, .name = spec.name};
  fit.applicable = std::any_of(problem.trials().begin(), problem.trials().end(),
                               [&](const PreparedTrial& t) { return spec.acts_on_kind(t.trial->kind); });
  fit.train_error_before = problem.training_error(base_training);
  const UnitSums before = problem.heldout_sums(base_full);
  fit.heldout_error_before = problem.heldout_error(before);
  if (!fit.applicable) {
    fit.heldout_error_after = fit.heldout_error_before;
    fit.train_error_after = fit.train_error_before;
    return fit;
  }
  const std::size_t n = spec.parameters.size();
  const auto variant_at = [&](const std::vector<double>& values) {
    ModelVariant v = base;
    apply_effect(id, values, v);
    return v;
  };
  const auto objective_at = [&](const std::vector<double>& values) {
    ++fit.evaluations;
    try {
      Evaluation e = problem.evaluate(variant_at(values), /*training_only=*/true, &spec);
      for (std::size_t t = 0; t < problem.size(); ++t) {
        if (e.predictions[t].empty()) e.predictions[t] = base_training[t];
      }
      const double error = problem.training_error(e.predictions);
      return std::isfinite(error) ? error : kInfeasible;
    } catch (const std::exception&) {  // an unphysical device (physics::InvalidParameter) or a diverged replay
      return kInfeasible;
    }
  };
  // A coarse start grid in the unit cube (the search is local), then BOBYQA from its best point.
  std::vector<double> best_u(n);
  const std::vector<double> start = fit_start(id, base.device);
  for (std::size_t i = 0; i < n; ++i) best_u[i] = to_unit(spec.parameters[i], start[i]);
  const auto values_of = [&](const std::vector<double>& u) {
    std::vector<double> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = from_unit(spec.parameters[i], u[i]);
    return v;
  };
  double best = objective_at(values_of(best_u));
  const std::vector<double> levels = n == 1 ? std::vector<double>{0.05, 0.25, 0.5, 0.75, 0.95}
                                            : std::vector<double>{0.2, 0.5, 0.8};
  std::vector<std::size_t> index(n, 0);
  for (bool more = true; more;) {
    std::vector<double> u(n);
    for (std::size_t i = 0; i < n; ++i) u[i] = levels[index[i]];
    // One parameter: five levels; two or three: the corners and centre of the 3^n grid (sum of indices even).
    std::size_t index_sum = 0;
    for (std::size_t i = 0; i < n; ++i) index_sum += index[i];
    if (n == 1 || index_sum % 2 == 0) {
      const double value = objective_at(values_of(u));
      if (value < best) {
        best = value;
        best_u = u;
      }
    }
    more = false;
    for (std::size_t i = 0; i < n && !more; ++i) {
      if (++index[i] < levels.size()) more = true;
      else index[i] = 0;
    }
  }
  std::vector<double> u = best_u;
  nlopt::opt search(nlopt::LN_BOBYQA, static_cast<unsigned>(n));
  search.set_lower_bounds(std::vector<double>(n, 0.0));
  search.set_upper_bounds(std::vector<double>(n, 1.0));
  search.set_initial_step(std::vector<double>(n, 0.08));
  search.set_xtol_abs(1e-4);
  search.set_ftol_rel(1e-7);
  search.set_maxeval(options.max_evaluations);
  struct Context {
    const decltype(values_of)* to_values;
    const decltype(objective_at)* objective;
  } context{&values_of, &objective_at};
  search.set_min_objective(
      [](unsigned dims, const double* x, double*, void* data) {
        const auto* c = static_cast<const Context*>(data);
        return (*c->objective)((*c->to_values)(std::vector<double>(x, x + dims)));
      },
      &context);
  double value = best;
  try {
    search.optimize(u, value);
  } catch (const std::exception&) {
    // NLopt's roundoff-limited and similar ends keep the best point found.
  }
  if (!(value <= best)) u = best_u;
  fit.values = values_of(u);
  fit.params = describe_values(id, fit.values, nominal);
  fit.train_error_after = std::min(value, best);

  // Held out: the full replay with the fitted effect.
  const ModelVariant fitted = variant_at(fit.values);
  Evaluation full = problem.evaluate(fitted, /*training_only=*/false, &spec);
  for (std::size_t t = 0; t < problem.size(); ++t) {
    if (full.predictions[t].empty()) full.predictions[t] = base_full[t];
  }
  const UnitSums after = problem.heldout_sums(full.predictions);
  fit.heldout_error_after = problem.heldout_error(after);
  fit.shrink_fraction =
      fit.heldout_error_before > 0.0 ? (fit.heldout_error_before - fit.heldout_error_after) / fit.heldout_error_before : 0.0;
  std::tie(fit.ci_low, fit.ci_high) = bootstrap_interval(problem, before, after, options.bootstrap, seed);
  fit.score = fit.shrink_fraction - options.parameter_penalty * static_cast<double>(n);
  return fit;
}

}  // namespace

Diagnosis diagnose(RealData data, const sim::DeviceDescription& nominal_device, ReplayEngine& engine,
                   const DiagnosisOptions& options) {
  Diagnosis d;
  d.data = std::move(data);
  d.problems = d.data.problems;
  const ModelVariant nominal{.device = nominal_device};
  // Trials the model cannot replay are reported and left out.
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
  const auto nothing_left = [&] {
    return std::runtime_error(d.problems.empty() ? std::string("no trial logs found to diagnose (softwrist.log/1 sidecars)")
                                                 : "no trial left to diagnose (see the problems listed above)");
  };
  if (d.data.trials.empty()) throw nothing_left();
  d.prepared = prepare(d.data, engine, nominal);
  // A trial whose noise cannot be estimated (constant data) cannot be weighed against the others.
  for (auto it = d.prepared.begin(); it != d.prepared.end();) {
    if (!(it->noise > 0.0)) {
      d.problems.push_back({it->trial->file, fmt::format("{}: its repeat-to-repeat noise is zero; it cannot be weighed",
                                                         it->name)});
      it = d.prepared.erase(it);
    } else {
      ++it;
    }
  }
  if (d.prepared.empty()) throw nothing_left();
  Problem problem(d.prepared, engine);

  // 1-2. Replay with the nominal model; localise.
  const Evaluation nominal_full = problem.evaluate(nominal, false);
  const Evaluation nominal_training = problem.evaluate(nominal, true);
  d.nominal_predictions = nominal_full.predictions;
  std::vector<std::vector<double>> residuals;
  for (std::size_t t = 0; t < problem.size(); ++t) residuals.push_back(residuals_of(d.prepared[t], nominal_full.predictions[t]));
  d.localization = localize(d.prepared, residuals, nominal_device, options.alpha);
  d.heldout_nominal = problem.heldout_error(problem.heldout_sums(nominal_full.predictions));

  // Each trial's whole gap test, Bonferroni over the trials.
  bool gap_significant = false;
  const double trial_alpha = options.alpha / static_cast<double>(problem.size());
  const auto trial_test = [&](std::size_t t, const std::vector<double>& r) {
    std::vector<std::size_t> all(r.size());
    std::iota(all.begin(), all.end(), 0);
    return group_test(d.prepared[t], r, all);
  };
  const auto rms = [](const std::vector<double>& r) {
    double ss = 0.0;
    for (double v : r) ss += v * v;
    return std::sqrt(ss / static_cast<double>(r.size()));
  };
  for (std::size_t t = 0; t < problem.size(); ++t) {
    const LocalizationEntry e = trial_test(t, residuals[t]);
    const PreparedTrial& p = d.prepared[t];
    TrialGap gap{.experiment = p.name, .kind = p.trial->kind, .unit = p.unit, .noise = p.noise,
                 .noise_source = p.noise_source, .p_value = e.p_value, .significant = e.p_value < trial_alpha,
                 .points = p.points.size()};
    gap.rms_nominal = rms(residuals[t]);
    gap_significant = gap_significant || gap.significant;
    d.trials.push_back(gap);
  }

  // 3. Each effect alone on the nominal model.
  std::vector<EffectId> ids = options.effects;
  if (ids.empty()) {
    for (const auto& spec : effect_catalogue()) ids.push_back(spec.id);
  }
  d.effects.resize(ids.size());
  parallel_for(static_cast<int>(ids.size()), options.jobs, [&](int k) {
    d.effects[static_cast<std::size_t>(k)] =
        fit_effect(problem, ids[static_cast<std::size_t>(k)], nominal, nominal_training.predictions,
                   nominal_full.predictions, nominal_device, options, options.seed + static_cast<std::uint64_t>(k));
  });
  std::stable_sort(d.effects.begin(), d.effects.end(), [](const EffectFit& a, const EffectFit& b) {
    if (a.applicable != b.applicable) return a.applicable;
    return a.score > b.score;
  });

  // Greedy combination: the best effect first, then whichever of the next candidates cuts the remaining held-out
  // error most, while each cut is at least min_gain of it and its bootstrap interval stays above zero.
  const auto helps = [&](const EffectFit& f) { return f.applicable && f.shrink_fraction >= options.min_gain && f.ci_low > 0.0; };
  ModelVariant current = nominal;
  std::vector<std::vector<double>> current_training = nominal_training.predictions, current_full = nominal_full.predictions;
  std::vector<EffectId> candidates;
  for (const auto& f : d.effects) {
    if (helps(f)) candidates.push_back(f.id);
  }
  std::uint64_t round_seed = options.seed + 1000;
  while (!candidates.empty() && static_cast<int>(d.combination.size()) < options.max_combined) {
    std::vector<EffectFit> tries;
    if (d.combination.empty()) {
      tries.push_back(*std::find_if(d.effects.begin(), d.effects.end(), [&](const EffectFit& f) { return f.id == candidates.front(); }));
    } else {
      const std::size_t count = std::min<std::size_t>(3, candidates.size());
      tries.resize(count);
      parallel_for(static_cast<int>(count), options.jobs, [&](int k) {
        tries[static_cast<std::size_t>(k)] = fit_effect(problem, candidates[static_cast<std::size_t>(k)], current,
                                                        current_training, current_full, nominal_device, options,
                                                        round_seed + static_cast<std::uint64_t>(k));
      });
      round_seed += 100;
    }
    const auto best = std::max_element(tries.begin(), tries.end(),
                                       [](const EffectFit& a, const EffectFit& b) { return a.score < b.score; });
    if (!helps(*best)) break;
    apply_effect(best->id, best->values, current);
    candidates.erase(std::find(candidates.begin(), candidates.end(), best->id));
    d.combination.push_back(*best);
    current_training = problem.evaluate(current, true).predictions;
    current_full = problem.evaluate(current, false).predictions;
  }
  d.corrected.emplace(current);
  d.corrected_predictions = current_full;
  d.heldout_corrected = problem.heldout_error(problem.heldout_sums(current_full));
  // The gap to explain: the trials whose nominal residual is significant (the others only add their noise floor,
  // which no effect removes).
  std::vector<bool> gap_trials;
  for (const auto& t : d.trials) gap_trials.push_back(t.significant);
  d.gap_nominal = problem.heldout_error(problem.heldout_sums(nominal_full.predictions), nullptr, &gap_trials);
  d.gap_corrected = problem.heldout_error(problem.heldout_sums(current_full), nullptr, &gap_trials);
  for (std::size_t t = 0; t < problem.size(); ++t) {
    const std::vector<double> r = residuals_of(d.prepared[t], current_full[t]);
    d.trials[t].rms_corrected = rms(r);
    d.remaining_gap_significant = d.remaining_gap_significant || trial_test(t, r).p_value < trial_alpha;
  }

  // Verdict.
  const double closed = d.gap_closed();
  if (!gap_significant) {
    d.verdict = "none";
    d.reason = fmt::format("no trial differs from the nominal model beyond its repeat-to-repeat noise (F test, "
                           "alpha {} over {} trials)", options.alpha, problem.size());
  } else if (d.heldout_nominal < options.min_gap) {
    d.verdict = "none";
    d.reason = fmt::format("the nominal model's systematic residual is {:.2f} of the noise on held-out data (below "
                           "{}): detectable in this much data, but within the noise of a measurement",
                           d.heldout_nominal, options.min_gap);
  } else if (!d.combination.empty() && closed >= options.explained_fraction) {
    d.verdict = d.combination.front().name;
    d.reason = fmt::format("{} closes {:.0f} % of the held-out gap on its own ({:.0f} % with the combination)",
                           d.combination.front().name, 100.0 * d.combination.front().shrink_fraction, 100.0 * closed);
  } else {
    d.verdict = "unexplained";
    d.reason = d.combination.empty()
                   ? "the gap is significant and no catalogue effect reduces the held-out error meaningfully"
                   : fmt::format("the gap is significant and the best combination closes only {:.0f} % of it", 100.0 * closed);
  }
  return d;
}

nlohmann::json to_json(const Diagnosis& d) {
  const auto effect_json = [](const EffectFit& f) {
    nlohmann::json params = nlohmann::json::object();
    for (const auto& [name, value] : f.params) params[name] = value;
    return nlohmann::json{{"name", f.name},
                          {"applicable", f.applicable},
                          {"params", params},
                          {"heldout_error_before", f.heldout_error_before},
                          {"heldout_error_after", f.heldout_error_after},
                          {"shrink_fraction", f.shrink_fraction},
                          {"ci_low", f.ci_low},
                          {"ci_high", f.ci_high},
                          {"score", f.score},
                          {"train_error_before", f.train_error_before},
                          {"train_error_after", f.train_error_after},
                          {"evaluations", f.evaluations}};
  };
  nlohmann::json j;
  j["verdict"] = d.verdict;
  j["reason"] = d.reason;
  j["error_metric"] = kErrorMetric;
  j["error_metric_description"] =
      "per trial sqrt(max(0, mean((measured - model)/noise)^2 - 1)) over held-out measurements: the systematic "
      "residual in units of the repeat-to-repeat noise; averaged over the trials of each kind, then over the kinds";
  j["heldout_error_nominal"] = d.heldout_nominal;
  j["heldout_error_corrected"] = d.heldout_corrected;
  j["gap_error_nominal"] = d.gap_nominal;
  j["gap_error_corrected"] = d.gap_corrected;
  j["gap_closed"] = d.gap_closed();
  j["remaining_gap_significant"] = d.remaining_gap_significant;
  j["effects"] = nlohmann::json::array();
  for (const auto& f : d.effects) j["effects"].push_back(effect_json(f));
  j["combination"] = nlohmann::json::array();
  for (const auto& f : d.combination) j["combination"].push_back(effect_json(f));
  j["localization"] = nlohmann::json::array();
  for (const auto& e : d.localization) {
    nlohmann::json entry{{"experiment", e.experiment}, {"where", e.where},  {"residual", e.residual},
                         {"noise", e.noise},           {"unit", e.unit},    {"p_value", e.p_value},
                         {"significant", e.significant}, {"count", e.count}};
    j["localization"].push_back(entry);
  }
  j["trials"] = nlohmann::json::array();
  for (const auto& t : d.trials) {
    j["trials"].push_back({{"experiment", t.experiment}, {"kind", to_string(t.kind)}, {"unit", t.unit},
                           {"noise", t.noise}, {"noise_source", t.noise_source}, {"rms_nominal", t.rms_nominal},
                           {"rms_corrected", t.rms_corrected}, {"p_value", t.p_value},
                           {"significant", t.significant}, {"points", t.points}});
  }
  j["skipped"] = nlohmann::json::array();
  for (const auto& p : d.problems) j["skipped"].push_back({{"file", p.file}, {"reason", p.reason}});
  return j;
}

}  // namespace softwrist::diagnosis
