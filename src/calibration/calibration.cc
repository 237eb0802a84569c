#include "calibration/calibration.h"

#include <algorithm>
#include <fstream>

#include <fmt/format.h>

#include "bridge_apps/hardware_trial.h"
#include "diagnosis/diagnosis_report.h"
#include "diagnosis/effects.h"
#include "diagnosis/real_data.h"
#include "diagnosis/replay.h"
#include "experiments/tracking.h"
#include "sim/plugins.h"

namespace softwrist::calibration {
namespace {

namespace fs = std::filesystem;
using diagnosis::EffectId;

const experiments::Tracking& routine_of(const experiments::ExperimentConfig& config,
                                        const experiments::Experiment& experiment) {
  const auto* tracking = dynamic_cast<const experiments::Tracking*>(&experiment);
  if (!tracking || tracking->excitation().empty()) {
    throw std::runtime_error(fmt::format(
        "{}: not a calibration routine (a tracking experiment whose one controller is \"excitation\")", config.source));
  }
  return *tracking;
}

}  // namespace

std::vector<EffectId> identifiable_effects() {
  return {EffectId::kRegulatorLag, EffectId::kMountStretch, EffectId::kPassiveWrist, EffectId::kHysteresis};
}

std::vector<Unidentifiable> unidentifiable_effects() {
  return {{"fpam_params",
           "the fPAM's radius and maximum contraction set its force at each length, as the mounts' stretch does: "
           "with angles alone the two trade off (the tensile test of Fig. TensileTest separates them)"},
          {"wrap_geometry",
           "the wrist's wrapping radius scales every muscle's moment arm, which angles alone cannot tell from the "
           "fPAM's force (a torque sensor or motion capture of the muscle's path can)"},
          {"imu_bias",
           "the angles are zeroed at the neutral wrist before the routine, which removes a fixed offset; a latency "
           "of the IMUs delays the angles as the regulators' dead time does, and only the pressures' timing is "
           "measured"}};
}

RoutineRecord run_routine(const experiments::ExperimentConfig& config, bridge::BridgePlant& plant,
                          const fs::path& log_dir, bool overwrite) {
  const std::unique_ptr<experiments::Experiment> experiment = experiments::make_experiment(config);
  const experiments::Tracking& routine = routine_of(config, *experiment);
  RoutineRecord record{.log_dir = log_dir, .planned_s = control::routine_duration_s(routine.excitation())};
  double peak_kpa = 0.0;
  for (const control::ExcitationSegment& s : routine.excitation()) {
    for (std::size_t m = 0; m < 4; ++m) peak_kpa = std::max({peak_kpa, s.from_kpa[m], s.to_kpa[m]});
  }
  if (peak_kpa > plant.max_pressure_kpa()) {
    throw std::runtime_error(
        fmt::format("{}: the routine reaches {} kPa, above this bridge's limit of {} kPa; lower "
                    "its step_levels_kpa and co_contraction_kpa",
                    config.source, peak_kpa, plant.max_pressure_kpa()));
  }
  const bridge::TrialResult result = bridge::run_trial(config, plant, {.out = log_dir, .overwrite = overwrite});
  const double period_s = routine.make_controllers().front()->period_s();
  record.run_s = std::min(record.planned_s, static_cast<double>(result.rows_logged) * period_s);
  record.fault = result.fault;
  // The parts of the routine that did not run to their end.
  double end = 0.0;
  for (const control::ExcitationSegment& s : routine.excitation()) {
    end += s.duration_s;
    const bool missing = end > record.run_s + 1e-9;
    if (missing && (record.parts_not_run.empty() || record.parts_not_run.back() != s.part)) {
      record.parts_not_run.push_back(s.part);
    }
  }
  return record;
}

Calibration calibrate_from_logs(const fs::path& log_dir, const sim::DeviceDescription& nominal,
                                const CalibrationOptions& options) {
  diagnosis::DiagnosisOptions d{
      .effects = identifiable_effects(), .jobs = options.jobs, .bootstrap = options.bootstrap};
  // A calibration identifies every parameter it can: no tolerance excuses a difference from the nominal, and an
  // effect joins the corrected model when it cuts the remaining held-out error by 2 % (the diagnosis asks 10 % before
  // it calls an effect a cause), as many as there are, and their parameters are then refitted together.
  d.tolerances = diagnosis::Tolerances::none();
  d.min_gain = 0.02;
  d.max_combined = static_cast<int>(d.effects.size());
  d.joint_refit_evaluations = options.refit_evaluations;
  // A calibration wants the parameters, not the simplest cause: the lowest held-out error leads each round. Among
  // fits the held-out part cannot tell apart, the fewest parameters (the diagnosis's one-standard-error rule) gave
  // the routine's holds to the mounts' one stiffness before the relaxed wrist's three, and the mounts then took the
  // stiffer wrist too (K_series 4.4 for 10.0 N/cm^2, passive_wrist left out).
  d.one_se_rule = false;
  diagnosis::RealData data = diagnosis::load_real_data(log_dir);
  if (data.trials.empty()) {
    std::string why;
    for (const auto& p : data.problems) why += fmt::format("; {}: {}", p.file, p.reason);
    throw std::runtime_error(fmt::format("{}: no trial to calibrate from{}", log_dir.string(), why));
  }
  diagnosis::ReplayEngine engine(sim::PluginSet::Default());
  Calibration c{.diagnosis = diagnosis::diagnose(std::move(data), nominal, engine, d), .calibrated = nominal};
  const diagnosis::Diagnosis& dx = c.diagnosis;
  if (dx.corrected) c.calibrated = dx.corrected->device;
  c.calibrated.routing = dx.routing;  // the routing the data chose (diagnosis.h), in the calibrated placement file
  c.parameters = diagnosis::combination_intervals(dx, nominal, engine);
  for (const auto& f : dx.combination) c.effects_applied.push_back(f.name);
  for (const auto& f : dx.effects) {
    if (std::find(c.effects_applied.begin(), c.effects_applied.end(), f.name) != c.effects_applied.end()) continue;
    c.not_identified.push_back(
        {f.name, f.applicable ? fmt::format("fitted alone it cut the held-out error by {:.1f} % (95 % interval "
                                            "{:.1f} to {:.1f} %): the data do not tell it from the nominal, which is "
                                            "kept",
                                            100 * f.shrink_fraction, 100 * f.ci_low, 100 * f.ci_high)
                              : "no recorded data act on it"});
  }
  for (const auto& p : c.parameters) {
    if (p.relative_width > options.identified_width) {
      c.not_identified.push_back(
          {p.effect + "." + p.name,
           fmt::format("fitted {:.4g} but its 95 % interval {:.4g} to {:.4g} spans {:.0f} % of its range: applied, "
                       "poorly determined",
                       p.value, p.low, p.high, 100 * p.relative_width)});
    }
  }
  for (const auto& u : unidentifiable_effects()) c.not_identified.push_back(u);
  if (dx.corrected && dx.corrected->regulator_dead_time > 0.0) {
    c.not_in_placement.push_back(fmt::format("regulator dead time {:.4g} s (add it to the controller's lead_s by hand)",
                                             dx.corrected->regulator_dead_time));
  }
  if (dx.corrected && dx.corrected->rom_residual_fraction >= 0.005) {
    c.not_in_placement.push_back(fmt::format(
        "{:.0f} % of the previous range-of-motion condition's pressure left when the angles were zeroed (lengthen "
        "the protocol's pause before zeroing)",
        100.0 * dx.corrected->rom_residual_fraction));
  }
  return c;
}

nlohmann::json to_json(const RoutineRecord& routine) {
  return {{"log", routine.log_dir.string()},
          {"planned_s", routine.planned_s},
          {"run_s", routine.run_s},
          {"fault", routine.fault ? nlohmann::json(*routine.fault) : nlohmann::json(nullptr)},
          {"parts_not_run", routine.parts_not_run}};
}

nlohmann::json write_calibration(const Calibration& c, const RoutineRecord& routine, const fs::path& dir,
                                 double wall_s) {
  fs::create_directories(dir);
  std::ofstream(dir / "calibrated.json") << sim::device_to_json(c.calibrated);
  diagnosis::write_diagnosis_report(c.diagnosis, dir / "diagnosis", {.plots = false, .wall_s = wall_s});
  nlohmann::json parameters = nlohmann::json::array();
  for (const auto& p : c.parameters) {
    parameters.push_back({{"effect", p.effect},
                          {"parameter", p.name},
                          {"value", p.value},
                          {"ci95", {p.low, p.high}},
                          {"relative_width", p.relative_width}});
  }
  nlohmann::json not_identified = nlohmann::json::array();
  for (const auto& u : c.not_identified) not_identified.push_back({{"what", u.effect}, {"why", u.reason}});
  for (const std::string& part : routine.parts_not_run) {
    not_identified.push_back(
        {{"what", part},
         {"why", fmt::format("did not run (the routine stopped: {}); the fitted values rest on the parts that ran and "
                             "are applied to all four muscles",
                             routine.fault.value_or("before its end"))}});
  }
  const nlohmann::json out = {{"calibrated", "calibrated.json"},
                              {"effects_applied", c.effects_applied},
                              {"parameters", parameters},
                              {"not_identified", not_identified},
                              {"not_in_placement", c.not_in_placement},
                              {"fit",
                               {{"heldout_error_nominal", c.diagnosis.heldout_nominal},
                                {"heldout_error_calibrated", c.diagnosis.heldout_corrected},
                                {"error_metric", diagnosis::kErrorMetric}}},
                              {"routine", to_json(routine)},
                              {"wall_s", wall_s}};
  std::ofstream(dir / "calibration.json") << out.dump(2) << '\n';
  return out;
}

}  // namespace softwrist::calibration
