#include "diagnosis/tolerance.h"

#include <algorithm>
#include <cmath>

#include "io/json_reader.h"
#include "io/text_file.h"

namespace softwrist::diagnosis {
namespace {

// The fields of a tolerance file, with where each lives in Tolerances, the factor from the file's unit to SI and the
// value it must stay below.
struct Field {
  const char* name;
  double Tolerances::*member;
  double to_si;
  double below;
  const char* range;  // why `below`
};
constexpr double kMm = 1e-3, kDeg = units::deg_to_rad(1.0), kKpa = units::kpa_to_pa(1.0);
constexpr Field kFields[] = {
    {"r0_fraction", &Tolerances::r0_fraction, 1.0, 1.0, "a fraction"},
    {"eps_max", &Tolerances::eps_max, 1.0, 0.08, "the fit's range"},
    {"muscle_r0_fraction", &Tolerances::muscle_r0_fraction, 1.0, 1.0, "a fraction"},
    {"muscle_eps_max", &Tolerances::muscle_eps_max, 1.0, 0.08, "the fit's range"},
    {"wrist_radius_fraction", &Tolerances::wrist_radius_fraction, 1.0, 1.0, "a fraction"},
    {"mount_stiffness_fraction", &Tolerances::mount_stiffness_fraction, 1.0, 1.0, "a fraction"},
    {"passive_stiffness_fraction", &Tolerances::passive_stiffness_fraction, 1.0, 1.0, "a fraction"},
    {"passive_damping_fraction", &Tolerances::passive_damping_fraction, 1.0, 1.0, "a fraction"},
    {"regulator_time_constant_fraction", &Tolerances::regulator_time_constant_fraction, 1.0, 1.0, "a fraction"},
    {"anchor_mm", &Tolerances::anchor, kMm, 20.0, "an anchor known within 2 cm"},
    {"rest_length_mm", &Tolerances::rest_length, kMm, 20.0, "a length known within 2 cm"},
    {"passive_range_margin_deg", &Tolerances::passive_range_margin, kDeg, 45.0, "a joint's passive range"},
    {"monitor_offset_kpa", &Tolerances::monitor_offset, kKpa, 10.0, "a monitor known within 10 kPa"},
    {"monitor_gain_fraction", &Tolerances::monitor_gain_fraction, 1.0, 0.2, "a monitor known within 20 %"},
};

std::pair<double, double> around(double value, double fraction) {
  return {value * (1.0 - fraction), value * (1.0 + fraction)};
}

}  // namespace

Tolerances read_tolerances(const std::filesystem::path& file) {
  const nlohmann::json json = io::parse_json(io::read_text_file(file), file.string());
  io::JsonReader reader(json, file.string(), "");
  Tolerances t;
  for (const Field& f : kFields) {
    const double v = reader.non_negative(f.name, t.*f.member / f.to_si);
    if (v >= f.below) reader.fail(f.name, fmt::format("must be below {} ({}), got {}", f.below, f.range, v));
    t.*f.member = v * f.to_si;
  }
  reader.finish();
  return t;
}

nlohmann::json to_json(const Tolerances& tolerances) {
  nlohmann::json j = nlohmann::json::object();
  for (const Field& f : kFields) j[f.name] = tolerances.*f.member / f.to_si;
  return j;
}

std::optional<std::vector<std::pair<double, double>>> tolerance_box(EffectId id, const sim::DeviceDescription& nominal,
                                                                    const Tolerances& t) {
  const EffectSpec& spec = effect_spec(id);
  // Zero-width at the neutral values (or the nominal's own, fit_start), then each parameter the tolerances free.
  std::vector<std::pair<double, double>> box;
  for (double v : fit_start(id, nominal)) box.emplace_back(v, v);
  switch (id) {
    case EffectId::kMountStretch:  // only a nominal that stretches has a stiffness to be uncertain about
      if (nominal.stretch_mode != physics::StretchMode::kNone)
        box[0] = around(box[0].first, t.mount_stiffness_fraction);
      break;
    case EffectId::kFpamParams:
      box[0] = around(1.0, t.r0_fraction);
      box[1] = {-t.eps_max, t.eps_max};
      break;
    case EffectId::kRegulatorLag:
      box[0] = around(nominal.regulator.time_constant, t.regulator_time_constant_fraction);
      break;
    case EffectId::kWrapGeometry:
      box[0] = around(1.0, t.wrist_radius_fraction);
      break;
    case EffectId::kPassiveWrist:
      box[0] = around(1.0, t.passive_stiffness_fraction);
      box[1] = around(1.0, t.passive_damping_fraction);
      break;
    case EffectId::kHysteresis:
    case EffectId::kImuBias:
      break;
  }
  bool free = false;
  for (std::size_t i = 0; i < box.size(); ++i) {
    const ParameterSpec& p = spec.parameters[i];
    box[i] = {std::clamp(box[i].first, p.lower, p.upper), std::clamp(box[i].second, p.lower, p.upper)};
    free = free || box[i].second > box[i].first;
  }
  if (!free) return std::nullopt;
  return box;
}

}  // namespace softwrist::diagnosis
