#include "diagnosis/tolerance.h"

#include <algorithm>
#include <cmath>

#include "io/json_reader.h"
#include "io/text_file.h"

namespace softwrist::diagnosis {
namespace {

// The fields of a tolerance file, with where each lives in Tolerances.
struct Field {
  const char* name;
  double Tolerances::*member;
  bool fraction;  // a relative tolerance, below 1
};
constexpr Field kFields[] = {
    {"r0_fraction", &Tolerances::r0_fraction, true},
    {"eps_max", &Tolerances::eps_max, false},
    {"wrist_radius_fraction", &Tolerances::wrist_radius_fraction, true},
    {"mount_stiffness_fraction", &Tolerances::mount_stiffness_fraction, true},
    {"passive_stiffness_fraction", &Tolerances::passive_stiffness_fraction, true},
    {"passive_damping_fraction", &Tolerances::passive_damping_fraction, true},
    {"regulator_time_constant_fraction", &Tolerances::regulator_time_constant_fraction, true},
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
    const double v = reader.non_negative(f.name, t.*f.member);
    if (f.fraction && v >= 1.0) reader.fail(f.name, fmt::format("must be a fraction below 1, got {}", v));
    if (!f.fraction && v >= 0.08) reader.fail(f.name, fmt::format("must be below 0.08 (the fit's range), got {}", v));
    t.*f.member = v;
  }
  reader.finish();
  return t;
}

nlohmann::json to_json(const Tolerances& tolerances) {
  nlohmann::json j = nlohmann::json::object();
  for (const Field& f : kFields) j[f.name] = tolerances.*f.member;
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
