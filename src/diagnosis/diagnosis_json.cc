#include "diagnosis/diagnosis.h"

#include <nlohmann/json.hpp>

// diagnosis.json (docs/diagnosis.md): the verdict, each effect's fit, the combination, the localisation and each
// trial's gap.
namespace softwrist::diagnosis {

namespace {

// The nominal within its tolerances: the tolerances given, what was fitted within them, and the held-out errors.
nlohmann::json tolerance_json(const ToleranceFit& tolerance) {
  nlohmann::json fitted = nlohmann::json::object();
  nlohmann::json moved = nlohmann::json::object();
  for (std::size_t k = 0; k < tolerance.params.size(); ++k) {
    fitted[tolerance.params[k].first] = tolerance.params[k].second;
    moved[tolerance.params[k].first] = tolerance.moved[k];
  }
  return {{"tolerances", to_json(tolerance.tolerances)},
          {"fitted", fitted},
          {"moved_fraction", moved},
          {"at_bound", tolerance.at_bound},
          {"heldout_error_as_placed", tolerance.heldout_error_as_placed},
          {"heldout_error_within", tolerance.heldout_error_within},
          {"train_error_before", tolerance.train_error_before},
          {"train_error_after", tolerance.train_error_after},
          {"evaluations", tolerance.evaluations}};
}

// An effect fitted beyond the tolerances, its training error (the selection's) and what it closes of the gap they
// leave; with `ranked` (the ranking's entries) also the bootstrap interval, which the joint refits of the default
// path do not compute.
nlohmann::json beyond_tolerance_json(const Diagnosis::BeyondTolerance& b, bool ranked) {
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [name, value] : b.params) params[name] = value;
  nlohmann::json j = {{"effect", b.effect},
                      {"params", params},
                      {"joint_with_tolerances", b.joint},
                      {"heldout_error_within", b.heldout_error_within},
                      {"heldout_error_with_effect", b.heldout_error_with_effect},
                      {"explained_fraction", b.explained_fraction},
                      {"explained_in_acted_on", b.explained_in_acted_on},
                      {"train_error_within", b.train_error_within},
                      {"train_error_with_effect", b.train_error_with_effect},
                      {"evaluations", b.evaluations}};
  if (ranked) {
    j["ci_low"] = b.ci_low;
    j["ci_high"] = b.ci_high;
  }
  return j;
}

nlohmann::json trial_json(const TrialGap& t) {
  return {{"experiment", t.experiment},
          {"kind", to_string(t.kind)},
          {"unit", t.unit},
          {"noise", t.noise},
          {"noise_source", t.noise_source},
          {"rms_nominal", t.rms_nominal},
          {"rms_corrected", t.rms_corrected},
          {"p_value", t.p_value},
          {"repeat_p_value", t.repeat_p_value},
          {"repeat_excess", t.repeat_excess},
          {"significant", t.significant},
          {"excess_nominal", t.excess_nominal},
          {"excess_corrected", t.excess_corrected},
          {"excess_within_tolerance", t.excess_within_tolerance},
          {"repeat_excess_within_tolerance", t.repeat_excess_within_tolerance},
          {"gap", t.gap},
          {"remaining_significant", t.remaining_significant},
          {"heldout_excess_leader_base", t.heldout_excess_leader_base},
          {"heldout_excess_within_alone", t.heldout_excess_within_alone},
          {"points", t.points}};
}

nlohmann::json drift_json(const TrialDrift& t) {
  return {{"experiment", t.experiment},           {"first_repetition", t.first_repetition},
          {"last_repetition", t.last_repetition}, {"conditions", t.conditions},
          {"shift_noise_units", t.shift},         {"t", t.t},
          {"significant", t.significant}};
}

nlohmann::json setting_change_json(const SettingChange& c) {
  return {{"experiment", c.experiment},
          {"muscle", c.muscle},
          {"angle_deg", c.angle_deg},
          {"settings", c.settings},
          {"conditions", c.conditions},
          {"first_repetition", c.first_repetition},
          {"last_repetition", c.last_repetition},
          {"spread", c.spread},
          {"unit", c.unit},
          {"spread_noise_units", c.spread_noise_units},
          {"ratio", c.ratio},
          {"significant", c.significant}};
}

// A JSON array of `to_entry` of each element.
template <typename T, typename F>
nlohmann::json array_of(const std::vector<T>& values, F&& to_entry) {
  nlohmann::json out = nlohmann::json::array();
  for (const T& v : values) out.push_back(to_entry(v));
  return out;
}

// The routing used, and where it was chosen each routing's errors (Diagnosis::routing_training_error and after).
nlohmann::json routing_json(const Diagnosis& d) {
  nlohmann::json j = {{"used", sim::to_string(d.routing)}};
  const std::pair<const char*, const std::vector<std::pair<sim::Routing, double>>*> errors[] = {
      {"training_error_as_placed", &d.routing_training_error},
      {"heldout_error_nominal_within_tolerances", &d.routing_heldout_error_nominal},
      {"heldout_error_best", &d.routing_heldout_error}};
  for (const auto& [name, by_routing] : errors) {
    for (const auto& [routing, error] : *by_routing) j[name][sim::to_string(routing)] = error;
  }
  return j;
}

// Named values as a JSON object.
nlohmann::json params_json(const std::vector<std::pair<std::string, double>>& values) {
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [name, value] : values) params[name] = value;
  return params;
}

// One effect's fit; where extended, with the base form it replaced.
nlohmann::json effect_json(const EffectFit& f) {
  nlohmann::json j{{"name", f.name},
                   {"applicable", f.applicable},
                   {"params", params_json(f.params)},
                   {"heldout_error_before", f.heldout_error_before},
                   {"heldout_error_after", f.heldout_error_after},
                   {"shrink_fraction", f.shrink_fraction},
                   {"shrink_where_acting", f.shrink_where_acting},
                   {"ci_low", f.ci_low},
                   {"ci_high", f.ci_high},
                   {"se_of_difference_to_best", f.se_of_difference_to_best},
                   {"within_one_se_of_best", f.within_one_se_of_best},
                   {"train_error_before", f.train_error_before},
                   {"train_error_after", f.train_error_after},
                   {"training_gap_after", f.training_gap_after},
                   {"evaluations", f.evaluations},
                   {"extended", f.extended},
                   {"within_tolerances", f.within_tolerances},
                   {"base_parameters", f.base_parameters},
                   {"heldout_excess_by_trial", f.heldout_excess_by_trial}};
  if (f.base_form)
    j["base_form"] = {{"params", params_json(f.base_form->params)},
                      {"shrink_fraction", f.base_form->shrink_fraction},
                      {"shrink_where_acting", f.base_form->shrink_where_acting}};
  return j;
}

}  // namespace

nlohmann::json to_json(const Diagnosis& d) {
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
  j["leading_effect"] = d.leading_effect;
  j["explained_fraction"] = d.explained_fraction;
  j["also_effects"] = d.also_effects;
  j["routing"] = routing_json(d);
  if (!d.beyond_tolerance.empty()) {
    j["beyond_tolerance"] = nlohmann::json::array();
    for (const auto& b : d.beyond_tolerance) j["beyond_tolerance"].push_back(beyond_tolerance_json(b, true));
  }
  if (d.beyond_tolerance_second) j["beyond_tolerance_second"] = beyond_tolerance_json(*d.beyond_tolerance_second, true);
  if (d.leader_beyond_tolerance)
    j["leader_beyond_tolerance"] = beyond_tolerance_json(*d.leader_beyond_tolerance, false);
  if (!d.runners_up_beyond_tolerance.empty()) {
    j["runners_up_beyond_tolerance"] = nlohmann::json::array();
    for (const auto& b : d.runners_up_beyond_tolerance)
      j["runners_up_beyond_tolerance"].push_back(beyond_tolerance_json(b, false));
  }
  j["tolerance"] = tolerance_json(d.tolerance);
  j["effects"] = array_of(d.effects, effect_json);
  j["combination"] = array_of(d.combination, effect_json);
  j["localization"] = nlohmann::json::array();
  for (const auto& e : d.localization) {
    nlohmann::json entry{{"experiment", e.experiment},
                         {"where", e.where},
                         {"residual", e.residual},
                         {"noise", e.noise},
                         {"unit", e.unit},
                         {"p_value", e.p_value},
                         {"significant", e.significant},
                         {"count", e.count}};
    j["localization"].push_back(entry);
  }
  j["trials"] = array_of(d.trials, trial_json);
  j["drift"] = array_of(d.drift, drift_json);
  j["setting_change"] = array_of(d.setting_changes, setting_change_json);
  j["skipped"] = array_of(d.problems, [](const FileProblem& p) {
    return nlohmann::json{{"file", p.file}, {"reason", p.reason}};
  });
  return j;
}

}  // namespace softwrist::diagnosis
