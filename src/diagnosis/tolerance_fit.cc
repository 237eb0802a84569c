#include "diagnosis/tolerance_fit.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "diagnosis/tolerance.h"
#include "optimize/bounded_least_squares.h"

namespace softwrist::diagnosis {
namespace {

// What one free parameter of the fit changes.
enum class KnobKind {
  kCatalogue,
  kHandAnchorD2,
  kHandAnchorW2,
  kRestLength,
  kWristRadius,
  kMuscleR0Scale,
  kMuscleEpsMaxShift,
  kLimit,
  kMonitorOffset,
  kMonitorGain
};

struct Knob {
  KnobKind kind;
  std::string name;           // as reported, in the unit of `nominal`
  double nominal, low, high;  // the box, in the reported unit
  double to_si = 1.0;         // reported unit -> the model's
  std::size_t effect = 0;     // kCatalogue: index into the fit's effects; its parameter
  std::size_t parameter = 0;
  std::filesystem::path rig;  // per rig: its placement file (empty: the diagnosis's --model)
  std::size_t index = 0;      // the muscle, the limit (flexion, extension, ulnar, radial) or the regulator
  bool cheap = false;         // changes only how a simulation is read (its replays are cached)
  // The catalogue effect whose tolerance this is: held at the nominal where that effect is fitted beyond the
  // tolerances (it then takes its whole value), as its own catalogue parameters are.
  std::optional<EffectId> owner;
};

// Which muscles each rig's trials use (by their placement file), and whether any uses the wrist's dynamics (range of
// motion, trajectories: the joint limits) or reads measured pressures.
struct Usage {
  std::map<std::filesystem::path, std::set<std::size_t>> muscles;
  std::set<std::filesystem::path> dynamic_rigs;
  bool pressures = false;
  bool pressures_drive_angles = false;  // the monitors' calibration then turns a trajectory's replayed drive
};

Usage usage_of(const GapProblem& problem) {
  Usage u;
  for (const PreparedTrial& prepared : problem.trials()) {
    const Trial& trial = *prepared.trial;
    const auto& rig = trial.conventions.placement;
    u.pressures = u.pressures || prepared.pressures;
    u.pressures_drive_angles = u.pressures_drive_angles || prepared.angles_from_measured_pressures;
    switch (trial.kind) {
      case TrialKind::kTorqueSweep:
        for (const SweepPoint& p : trial.sweep) u.muscles[rig].insert(static_cast<std::size_t>(p.muscle));
        break;
      case TrialKind::kRangeOfMotion:
        for (const RomPoint& p : trial.rom) u.muscles[rig].insert(static_cast<std::size_t>(p.muscle));
        u.dynamic_rigs.insert(rig);
        break;
      case TrialKind::kTrajectory:
        for (std::size_t m = 0; m < 4; ++m) u.muscles[rig].insert(m);
        u.dynamic_rigs.insert(rig);
        break;
      case TrialKind::kTensile:  // the fPAM alone: no placement
        break;
    }
  }
  return u;
}

constexpr const char* kLimitNames[] = {"flexion", "extension", "ulnar", "radial"};

std::string rig_name(const std::filesystem::path& rig) { return rig.empty() ? "model" : rig.stem().string(); }

// One muscle's knobs on one rig: its hand anchor, rest length and wrist radius, and where freed its own fPAM.
void add_muscle_knobs(const std::filesystem::path& rig, std::size_t m, const sim::MuscleMount& mount,
                      const Tolerances& t, std::vector<Knob>& knobs) {
  const std::string prefix = fmt::format("{}.{}.", rig_name(rig), sim::kMuscleNames[m]);
  // value and tolerance in SI; field names the reported unit, to_si converts it.
  const auto add = [&](KnobKind kind, const char* field, double value, double tolerance, double to_si,
                       std::optional<EffectId> owner = std::nullopt) {
    if (tolerance <= 0.0) return;
    knobs.push_back({.kind = kind,
                     .name = prefix + field,
                     .nominal = value / to_si,
                     .low = (value - tolerance) / to_si,
                     .high = (value + tolerance) / to_si,
                     .to_si = to_si,
                     .rig = rig,
                     .index = m,
                     .owner = owner});
  };
  constexpr double kCm = units::cm_to_m(1.0);
  add(KnobKind::kHandAnchorD2, "d2_cm", mount.placement.d2, t.anchor, kCm);
  add(KnobKind::kHandAnchorW2, "w2_cm", mount.placement.w2, t.anchor, kCm);
  add(KnobKind::kRestLength, "L0_cm", mount.rest_length, t.rest_length, kCm);
  // Each muscle's wrist radius is measured on its own, where that muscle crosses the wrist (the paper's 3.99 cm and
  // 3 cm), so each is off on its own: the fit frees each in place of wrap_geometry's one scale of them all.
  add(KnobKind::kWristRadius, "rw_cm", mount.wrist_radius, t.wrist_radius_fraction * mount.wrist_radius, kCm,
      EffectId::kWrapGeometry);
  // Its own fPAM about the table (which fpam_params' tolerance scales for them all): held at the muscle's own where
  // fpam_params is fitted beyond the tolerances, as the wrist radii are for wrap_geometry.
  add(KnobKind::kMuscleR0Scale, "r0_scale", mount.fpam_radius_scale, t.muscle_r0_fraction * mount.fpam_radius_scale,
      1.0, EffectId::kFpamParams);
  add(KnobKind::kMuscleEpsMaxShift, "eps_max_shift", mount.fpam_max_contraction_shift, t.muscle_eps_max, 1.0,
      EffectId::kFpamParams);
}

// The per-muscle, per-rig and per-regulator knobs the tolerances free.
void add_device_knobs(const GapProblem& problem, const ModelVariant& nominal, const Tolerances& t,
                      std::vector<Knob>& knobs) {
  const Usage usage = usage_of(problem);
  for (const auto& [rig, muscles] : usage.muscles) {
    const sim::DeviceDescription& device = rig.empty() ? nominal.device : nominal.rigs.at(rig);
    for (std::size_t m : muscles) add_muscle_knobs(rig, m, device.muscles[m], t, knobs);
  }
  for (const auto& rig : usage.dynamic_rigs) {
    if (t.passive_range_margin <= 0.0) break;
    const sim::PassiveWrist& w = (rig.empty() ? nominal.device : nominal.rigs.at(rig)).wrist;
    const double limits[] = {w.flexion_limit, w.extension_limit, w.ulnar_limit, w.radial_limit};
    for (std::size_t i = 0; i < 4; ++i) {
      const double deg = units::rad_to_deg(limits[i]);
      knobs.push_back({.kind = KnobKind::kLimit,
                       .name = fmt::format("{}.wrist.{}_limit_deg", rig_name(rig), kLimitNames[i]),
                       .nominal = deg,
                       .low = deg,
                       .high = deg + units::rad_to_deg(t.passive_range_margin),
                       .to_si = units::deg_to_rad(1.0),
                       .rig = rig,
                       .index = i});
    }
  }
  for (std::size_t m = 0; usage.pressures && m < 4; ++m) {
    const std::string prefix = fmt::format("monitor.{}", sim::kMuscleNames[m]);
    if (t.monitor_offset > 0.0) {
      const double kpa = units::pa_to_kpa(t.monitor_offset);
      knobs.push_back({.kind = KnobKind::kMonitorOffset,
                       .name = prefix + ".offset_kpa",
                       .nominal = 0.0,
                       .low = -kpa,
                       .high = kpa,
                       .to_si = units::kpa_to_pa(1.0),
                       .index = m,
                       .cheap = !usage.pressures_drive_angles});
    }
    if (t.monitor_gain_fraction > 0.0) {
      knobs.push_back({.kind = KnobKind::kMonitorGain,
                       .name = prefix + ".gain",
                       .nominal = 1.0,
                       .low = 1.0 - t.monitor_gain_fraction,
                       .high = 1.0 + t.monitor_gain_fraction,
                       .index = m,
                       .cheap = !usage.pressures_drive_angles});
    }
  }
}

// A knob's value applied to a copy of the nominal (per-device knobs before the catalogue's effects, which scale what
// the placement holds).
void apply_knob(const Knob& k, double value, ModelVariant& v) {
  const double si = value * k.to_si;
  sim::DeviceDescription& device = k.rig.empty() ? v.device : v.rigs.at(k.rig);
  switch (k.kind) {
    case KnobKind::kHandAnchorD2:
      device.muscles[k.index].placement.d2 = si;
      break;
    case KnobKind::kHandAnchorW2:
      device.muscles[k.index].placement.w2 = si;
      break;
    case KnobKind::kRestLength:
      device.muscles[k.index].rest_length = si;
      break;
    case KnobKind::kWristRadius:
      device.muscles[k.index].wrist_radius = si;
      break;
    case KnobKind::kMuscleR0Scale:
      device.muscles[k.index].fpam_radius_scale = si;
      break;
    case KnobKind::kMuscleEpsMaxShift:
      device.muscles[k.index].fpam_max_contraction_shift = si;
      break;
    case KnobKind::kLimit: {
      double* limits[] = {&device.wrist.flexion_limit, &device.wrist.extension_limit, &device.wrist.ulnar_limit,
                          &device.wrist.radial_limit};
      *limits[k.index] = si;
      break;
    }
    case KnobKind::kMonitorOffset:
      v.monitor_offset[k.index] = si;
      break;
    case KnobKind::kMonitorGain:
      v.monitor_gain[k.index] = si;
      break;
    case KnobKind::kCatalogue:
      break;
  }
}

// The catalogue's parameters with a free tolerance box, for every effect that acts on some trial, at the nominal's own
// values (fit_start): the effects in `ids` with their start values, and a knob for each free parameter. A rig whose
// placement has rigid mounts has no stiffness to be uncertain about.
void add_catalogue_knobs(const GapProblem& problem, const ModelVariant& nominal, const Tolerances& tolerances,
                         std::vector<EffectId>& ids, std::vector<std::vector<double>>& start,
                         std::vector<Knob>& knobs) {
  const bool rigid_rig = std::any_of(nominal.rigs.begin(), nominal.rigs.end(), [](const auto& rig) {
    return rig.second.stretch_mode == physics::StretchMode::kNone;
  });
  for (const EffectSpec& spec : effect_catalogue()) {
    const bool acts = std::any_of(problem.trials().begin(), problem.trials().end(),
                                  [&](const PreparedTrial& t) { return acts_on(spec, t); });
    // wrap_geometry's tolerance is each muscle's wrist radius (add_device_knobs).
    if (!acts || (spec.id == EffectId::kMountStretch && rigid_rig) || spec.id == EffectId::kWrapGeometry) continue;
    const auto box = tolerance_box(spec.id, nominal.device, tolerances);
    if (!box) continue;
    ids.push_back(spec.id);
    start.push_back(fit_start(spec.id, nominal.device));
    for (std::size_t i = 0; i < box->size(); ++i) {
      if ((*box)[i].second <= (*box)[i].first) continue;
      knobs.push_back({.kind = KnobKind::kCatalogue,
                       .name = fmt::format("{}.{}", spec.name, spec.parameters[i].name),
                       .nominal = std::clamp(start.back()[i], (*box)[i].first, (*box)[i].second),
                       .low = (*box)[i].first,
                       .high = (*box)[i].second,
                       .effect = ids.size() - 1,
                       .parameter = i,
                       .owner = spec.id});
    }
  }
}

// The fitted values, how far each moved into its box, and which ended at an edge of it that is not the nominal itself
// (within 2 % of the box's width): the device may lie beyond its tolerance there.
void report_knobs(const std::vector<Knob>& knobs, const std::vector<double>& x, ToleranceFit& fit) {
  for (std::size_t k = 0; k < knobs.size(); ++k) {
    const Knob& knob = knobs[k];
    fit.params.emplace_back(knob.name, x[k]);
    fit.boxes.emplace_back(knob.low, knob.high);
    const double side = x[k] >= knob.nominal ? knob.high - knob.nominal : knob.nominal - knob.low;
    fit.moved.push_back(side > 0.0 ? (x[k] - knob.nominal) / side : 0.0);
    const double edge = 0.02 * (knob.high - knob.low);
    if ((x[k] < knob.low + edge && knob.low < knob.nominal) || (x[k] > knob.high - edge && knob.high > knob.nominal))
      fit.at_bound.push_back(knob.name);
  }
}

// Every free parameter of the fit, and the model at a point of their boxes.
struct Setup {
  std::vector<EffectId> ids;               // catalogue effects with a free tolerance box
  std::vector<std::vector<double>> start;  // their values at the nominal
  std::vector<Knob> knobs;

  // The effects in `without` keep their own catalogue parameters at the nominal.
  ModelVariant variant_at(const ModelVariant& nominal, std::span<const double> x,
                          std::span<const EffectId> without = {}) const {
    const auto held = [&](EffectId id) { return std::find(without.begin(), without.end(), id) != without.end(); };
    ModelVariant v = nominal;
    std::vector<std::vector<double>> values = start;
    for (std::size_t k = 0; k < knobs.size(); ++k) {
      if (knobs[k].kind == KnobKind::kCatalogue) {
        values[knobs[k].effect][knobs[k].parameter] = x[k];
      } else if (!knobs[k].owner || !held(*knobs[k].owner)) {
        apply_knob(knobs[k], x[k], v);
      }
    }
    for (std::size_t e = 0; e < ids.size(); ++e) {
      if (!held(ids[e])) apply_effect(ids[e], values[e], v);
    }
    // The anchors and limits moved: each hand mount clear of its wrist surface over its reach, as a placement file's
    // (wrap_geometry checks it too, but only where it has a box of its own).
    sim::check_hand_mount_clearance(v.device);
    for (const auto& [placement, rig] : v.rigs) sim::check_hand_mount_clearance(rig);
    return v;
  }
};

Setup setup_of(const GapProblem& problem, const ModelVariant& nominal, const Tolerances& tolerances) {
  Setup s;
  add_catalogue_knobs(problem, nominal, tolerances, s.ids, s.start, s.knobs);
  add_device_knobs(problem, nominal, tolerances, s.knobs);
  return s;
}

// The training residuals of the model a point gives; none where the model cannot be built or replayed (an
// unphysical corner of a box, an anchor inside the wrist).
optimize::ResidualFunction residuals_of(const GapProblem& problem,
                                        std::function<ModelVariant(std::span<const double>)> model_at,
                                        Fidelity fidelity = Fidelity::kFine) {
  return [&problem, model_at, fidelity](std::span<const double> x) -> std::optional<std::vector<double>> {
    try {
      return problem.training_residuals(problem.evaluate(model_at(x), true, nullptr, fidelity));
    } catch (const std::exception&) {
      return std::nullopt;
    }
  };
}

optimize::LeastSquaresSettings settings_of(const std::vector<Knob>& knobs, const DiagnosisOptions& options) {
  optimize::LeastSquaresSettings settings{.max_evaluations = options.tolerance_evaluations, .jobs = options.jobs};
  for (const Knob& k : knobs) {
    settings.lower.push_back(k.low);
    settings.upper.push_back(k.high);
    settings.cheap.push_back(k.cheap);
  }
  return settings;
}

}  // namespace

ToleranceFit fit_within_tolerances(const GapProblem& problem, const ModelVariant& nominal,
                                   const DiagnosisOptions& options) {
  ToleranceFit fit{.tolerances = options.tolerances};
  const Setup setup = setup_of(problem, nominal, options.tolerances);
  std::vector<double> x0;
  for (const Knob& k : setup.knobs) x0.push_back(k.nominal);
  fit.variant.emplace(setup.variant_at(nominal, x0));
  if (setup.knobs.empty()) return fit;
  fit.train_error_before = problem.training_error(problem.evaluate(nominal, true));
  // The tolerances alone: residuals close to linear in them, where Broyden's updates save most of the differencing
  // (an effect's own parameters, fitted with them below, are not).
  optimize::LeastSquaresSettings settings = settings_of(setup.knobs, options);
  settings.secant_updates = true;
  const auto model_at = [&](std::span<const double> x) { return setup.variant_at(nominal, x); };
  if (problem.depends_on_step()) settings.difference_residuals = residuals_of(problem, model_at, Fidelity::kCoarse);
  const optimize::LeastSquaresResult found =
      optimize::minimize_least_squares(residuals_of(problem, model_at), x0, settings);
  fit.evaluations = found.evaluations;
  fit.train_error_after = std::min(found.cost, fit.train_error_before);
  const std::vector<double>& x = found.cost <= fit.train_error_before ? found.x : x0;
  fit.variant.emplace(setup.variant_at(nominal, x));
  report_knobs(setup.knobs, x, fit);
  return fit;
}

ModelVariant within_tolerances_without(const GapProblem& problem, const ModelVariant& nominal,
                                       const DiagnosisOptions& options, const ToleranceFit& within,
                                       std::span<const EffectId> ids, std::span<const double> tolerances) {
  const Setup setup = setup_of(problem, nominal, options.tolerances);
  if (setup.knobs.size() != within.params.size()) throw std::logic_error("the tolerance fit is not of these data");
  std::vector<double> x(tolerances.begin(), tolerances.end());
  if (x.empty()) {
    for (const auto& [name, value] : within.params) x.push_back(value);
  }
  if (x.size() != setup.knobs.size()) throw std::logic_error("tolerance values of other data");
  return setup.variant_at(nominal, x, ids);
}

JointFit fit_effect_within_tolerances(const GapProblem& problem, const ModelVariant& nominal,
                                      const DiagnosisOptions& options, const ToleranceFit& within, EffectId id,
                                      std::span<const double> start, std::span<const double> start_from_nominal) {
  const Setup setup = setup_of(problem, nominal, options.tolerances);
  if (setup.knobs.size() != within.params.size()) throw std::logic_error("the tolerance fit is not of these data");
  // The tolerances from where their fit ended (the effect's own at the nominal), then the effect's parameters in
  // the unit interval of its catalogue range; or the tolerances at the nominal with `start_from_nominal`.
  const EffectSpec& spec = effect_spec(id);
  std::vector<double> knobs_fitted, knobs_nominal;
  optimize::LeastSquaresSettings settings = settings_of(setup.knobs, options);
  for (std::size_t k = 0; k < setup.knobs.size(); ++k) {
    const Knob& knob = setup.knobs[k];
    const bool own = knob.owner == id;
    knobs_fitted.push_back(own ? knob.nominal : within.params[k].second);
    knobs_nominal.push_back(knob.nominal);
    if (own) settings.lower[k] = settings.upper[k] = knob.nominal;  // held (bounds equal: not searched)
  }
  for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
    settings.lower.push_back(0.0);
    settings.upper.push_back(1.0);
    settings.cheap.push_back(false);
  }
  // A start: the tolerance knobs, then the effect's values in the unit interval of its catalogue range.
  const auto start_at = [&](const std::vector<double>& knobs, std::span<const double> values) {
    std::vector<double> x = knobs;
    for (std::size_t i = 0; i < spec.parameters.size(); ++i) x.push_back(spec.parameters[i].to_unit(values[i]));
    return x;
  };
  const std::size_t n = setup.knobs.size();
  const auto values_at = [&](std::span<const double> x) {
    std::vector<double> values;
    for (std::size_t i = 0; i < spec.parameters.size(); ++i) values.push_back(spec.parameters[i].from_unit(x[n + i]));
    return values;
  };
  const auto model_at = [&](std::span<const double> x) {
    ModelVariant v = setup.variant_at(nominal, x.first(n), std::array{id});
    apply_effect(id, values_at(x), v);
    return v;
  };
  const optimize::ResidualFunction residuals = residuals_of(problem, model_at);
  if (problem.depends_on_step()) settings.difference_residuals = residuals_of(problem, model_at, Fidelity::kCoarse);
  int evaluations = 0;
  const auto cost = [&](const std::vector<double>& x) {
    ++evaluations;
    return sum_of_squares_or_infeasible(residuals(x));
  };
  std::vector<double> x0 = start_at(knobs_fitted, start);
  double x0_cost = cost(x0);
  if (!start_from_nominal.empty()) {  // the start whose training error is lower
    std::vector<double> from_nominal = start_at(knobs_nominal, start_from_nominal);
    if (const double c = cost(from_nominal); c < x0_cost) x0 = std::move(from_nominal), x0_cost = c;
  }
  // Where neither can be built or replayed (an effect fitted on another base, put on the tolerances as fitted: an
  // elliptical wrap surface with anchors the tolerance fit moved can hold a mount inside the surface), the effect at
  // its neutral value on the tolerances as fitted, then on the tolerances at their nominal values.
  if (!(x0_cost < kInfeasible)) {
    const std::vector<double> neutral = fit_start(id, nominal.device);
    x0 = start_at(knobs_fitted, neutral);
    if (!(cost(x0) < kInfeasible)) x0 = start_at(knobs_nominal, neutral);
  }
  const optimize::LeastSquaresResult found = optimize::minimize_least_squares(residuals, x0, settings);
  return {.variant = model_at(found.x),
          .values = values_at(found.x),
          .tolerances = std::vector<double>(found.x.begin(), found.x.begin() + static_cast<std::ptrdiff_t>(n)),
          .evaluations = evaluations + found.evaluations};
}

}  // namespace softwrist::diagnosis
