#include "fpam_config.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "physics/errors.h"
#include "physics/plausible_ranges.h"
#include "physics/units.h"

namespace softwrist::plugin {
namespace {

// Reads attributes of one instance, turning every problem into "actuator 'NAME': attribute 'KEY': problem".
class AttributeReader {
 public:
  AttributeReader(const PluginConfig& config, std::string_view actuator, std::string* error)
      : config_(config), actuator_(actuator), error_(error) {}

  bool ok() const { return ok_; }
  bool Fail(std::string_view key, const std::string& problem) {
    if (ok_) {
      *error_ = "actuator '" + std::string(actuator_) +
                "': " + (key.empty() ? std::string() : "attribute '" + std::string(key) + "': ") + problem;
    }
    ok_ = false;
    return false;
  }
  bool Has(std::string_view key) const { return config_.Get(key).has_value(); }

  std::vector<double> Numbers(std::string_view key) {
    std::vector<double> numbers;
    const auto text = config_.Get(key);
    if (!text) return Fail(key, "missing"), numbers;
    std::string_view rest = *text;
    while (ok_) {
      const auto comma = rest.find(',');
      const std::string_view item = rest.substr(0, comma);
      double value = 0.0;
      const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
      if (item.empty() || ec != std::errc() || end != item.data() + item.size() || !std::isfinite(value)) {
        Fail(key, "'" + std::string(item) + "' is not a finite number");
        break;
      }
      numbers.push_back(value);
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
    return numbers;
  }
  double Number(std::string_view key) {
    const auto numbers = Numbers(key);
    if (!ok_) return 0.0;
    if (numbers.size() != 1) return Fail(key, "expected one number"), 0.0;
    return numbers.front();
  }
  double Number(std::string_view key, double fallback) { return Has(key) ? Number(key) : fallback; }
  double Positive(std::string_view key, double fallback) {
    const double value = Number(key, fallback);
    if (ok_ && !(value > 0.0)) Fail(key, "must be > 0");
    return value;
  }

  std::string Text(std::string_view key, std::string_view fallback) {
    return config_.Get(key).value_or(std::string(fallback));
  }

 private:
  const PluginConfig& config_;
  std::string_view actuator_;
  std::string* error_;
  bool ok_ = true;
};

std::optional<physics::FpamParameters> ReadFpam(AttributeReader& read) {
  physics::FabricProperties fabric;
  fabric.elastic_modulus = read.Positive(FpamConfig::kElasticModulus, fabric.elastic_modulus);
  fabric.thickness = read.Positive(FpamConfig::kThickness, fabric.thickness);
  fabric.elastic_onset_contraction = read.Number(FpamConfig::kElasticOnset, fabric.elastic_onset_contraction);
  fabric.elastic_curvature = read.Number(FpamConfig::kElasticCurvature, fabric.elastic_curvature);
  if (!read.ok()) return std::nullopt;
  const bool constant = read.Has(FpamConfig::kRadius) || read.Has(FpamConfig::kMaxContraction);
  const bool table = read.Has(FpamConfig::kTablePressureKpa) || read.Has(FpamConfig::kTableRadius) ||
                     read.Has(FpamConfig::kTableMaxContraction);
  if (constant == table) {
    read.Fail("", "give either r0 and eps_max, or table_pressure_kpa, table_r0 and table_eps_max");
    return std::nullopt;
  }
  try {
    if (constant) {
      const double r0 = read.Number(FpamConfig::kRadius);
      const double eps_max = read.Number(FpamConfig::kMaxContraction);
      if (!read.ok()) return std::nullopt;
      return physics::FpamParameters::Constant(r0, eps_max, fabric);
    }
    const auto pressures = read.Numbers(FpamConfig::kTablePressureKpa);
    const auto radii = read.Numbers(FpamConfig::kTableRadius);
    const auto eps = read.Numbers(FpamConfig::kTableMaxContraction);
    if (!read.ok()) return std::nullopt;
    if (radii.size() != pressures.size() || eps.size() != pressures.size()) {
      read.Fail(FpamConfig::kTablePressureKpa, "table_pressure_kpa, table_r0 and table_eps_max differ in length");
      return std::nullopt;
    }
    std::vector<physics::FpamTableRow> rows;
    for (std::size_t i = 0; i < pressures.size(); ++i) {
      rows.push_back({units::kpa_to_pa(pressures[i]), radii[i], eps[i]});
    }
    return physics::FpamParameters::Table(rows, fabric);
  } catch (const physics::InvalidParameter& e) {
    read.Fail("", e.what());
    return std::nullopt;
  }
}

// routing=planar's path (FpamConfig::PlanarPath), validated as the physics core validates a placement.
std::optional<FpamConfig::PlanarPath> ReadPlanarPath(AttributeReader& read) {
  const std::string routing = read.Text(FpamConfig::kRouting, "spatial");
  const bool geometry =
      read.Has(FpamConfig::kPlacement) || read.Has(FpamConfig::kWristRadius) || read.Has(FpamConfig::kWrapSurface);
  if (routing == "spatial") {
    if (geometry) read.Fail(FpamConfig::kRouting, "placement, wrist_radius and wrap_surface need routing=planar");
    return std::nullopt;
  }
  if (routing != "planar") {
    read.Fail(FpamConfig::kRouting, "'" + routing + "' is not spatial or planar");
    return std::nullopt;
  }
  const auto placement = read.Numbers(FpamConfig::kPlacement);
  const double wrist_radius = read.Number(FpamConfig::kWristRadius);
  std::vector<double> surface{0.0, 0.0, 1.0};
  if (read.Has(FpamConfig::kWrapSurface)) surface = read.Numbers(FpamConfig::kWrapSurface);
  if (!read.ok()) return std::nullopt;
  if (placement.size() != 4) return read.Fail(FpamConfig::kPlacement, "expected d1,w1,d2,w2"), std::nullopt;
  if (surface.size() != 3) return read.Fail(FpamConfig::kWrapSurface, "expected x,y,aspect"), std::nullopt;
  FpamConfig::PlanarPath path{.placement = {placement[0], placement[1], placement[2], placement[3]},
                              .wrist_radius = wrist_radius,
                              .surface = {surface[0], surface[1], surface[2]}};
  try {
    physics::validate(path.placement, path.wrist_radius, path.surface);
  } catch (const physics::InvalidParameter& e) {
    read.Fail(FpamConfig::kPlacement, e.what());
    return std::nullopt;
  }
  return path;
}

std::string list(const std::vector<double>& values) {
  std::string out;
  for (const double v : values) out += (out.empty() ? "" : ",") + fmt::format("{:.10g}", v);
  return out;
}

}  // namespace

std::optional<FpamConfig> FpamConfig::FromConfig(const PluginConfig& config, std::string_view actuator_name,
                                                 std::string* error) {
  AttributeReader read(config, actuator_name, error);
  if (config.plugin_name() != kPluginName) {
    read.Fail("", "plugin '" + config.plugin_name() + "' is not " + std::string(kPluginName));
    return std::nullopt;
  }
  for (const auto& key : config.Keys()) {
    if (std::find(kAttributes.begin(), kAttributes.end(), key) == kAttributes.end()) {
      read.Fail(key, "unknown attribute");
      return std::nullopt;
    }
  }
  auto fpam = ReadFpam(read);
  if (!fpam) return std::nullopt;
  FpamConfig result{.law = {.fpam = std::move(*fpam)}};
  physics::MuscleLaw& law = result.law;
  if (read.Has(kRestLength)) {
    law.rest_length = read.Positive(kRestLength, 0.0);
  } else {
    read.Fail(kRestLength, "missing");
  }
  const std::string stretch = read.Text(kStretch, "none");
  const auto mode = physics::parse_stretch_mode(stretch);
  if (!mode) read.Fail(kStretch, "'" + stretch + "' is not none, oneshot or selfconsistent");
  law.stretch_mode = mode.value_or(physics::StretchMode::kNone);
  if (read.ok() && law.stretch_mode != physics::StretchMode::kNone) {
    if (!read.Has(kForearmStiffness)) read.Fail(kForearmStiffness, "must be given when the mounts stretch");
    if (!read.Has(kHandStiffness)) read.Fail(kHandStiffness, "must be given when the mounts stretch");
  }
  law.mount_stiffness = {.forearm = read.Number(kForearmStiffness, 0.0),
                         .hand = read.Number(kHandStiffness, 0.0),
                         .exponent = read.Number(kMountExponent, 2.0),
                         .preload = read.Number(kMountPreload, 0.0),
                         .shaped_share = read.Number(kMountShapedShare, 1.0)};
  if (read.ok()) {
    try {
      physics::validate(law);  // L0's range and a non-zero stiffness: the physics core's own rules
    } catch (const physics::InvalidParameter& e) {
      read.Fail("", e.what());
    }
  }
  result.max_pressure_kpa = read.Positive(kMaxPressureKpa, result.max_pressure_kpa);
  if (read.ok() && result.max_pressure_kpa > units::pa_to_kpa(physics::plausible::kMaxPressure)) {
    read.Fail(kMaxPressureKpa, "must be at most 1000 (kPa)");
  }
  physics::RegulatorResponse& regulator = result.regulator;
  regulator.time_constant = read.Positive(kTimeConstant, regulator.time_constant);
  if (read.ok() && !(regulator.time_constant >= physics::plausible::kMinTimeConstant &&
                     regulator.time_constant <= physics::plausible::kMaxTimeConstant)) {
    read.Fail(kTimeConstant, "must lie in [0.001, 100] (s; MuJoCo integrates the regulator in 1 ms steps)");
  }
  regulator.vent_time_constant = read.Number(kVentTimeConstant, 0.0);
  if (read.ok() && regulator.vent_time_constant != 0.0 &&
      !(regulator.vent_time_constant >= physics::plausible::kMinTimeConstant &&
        regulator.vent_time_constant <= physics::plausible::kMaxTimeConstant)) {
    read.Fail(kVentTimeConstant, "must be 0 (as time_constant) or lie in [0.001, 100] (s)");
  }
  regulator.second_order_time = read.Number(kSecondOrderTime, 0.0);
  if (read.ok() &&
      !(regulator.second_order_time >= 0.0 && regulator.second_order_time <= physics::plausible::kMaxTimeConstant)) {
    read.Fail(kSecondOrderTime, "must lie in [0, 100] (s; 0: a first-order regulator)");
  }
  result.hysteresis.fraction = read.Number(kHysteresis, 0.0);
  result.hysteresis.transition_length = read.Positive(kHysteresisLength, result.hysteresis.transition_length);
  result.hysteresis.friction_force = read.Number(kHysteresisFriction, 0.0);
  result.hysteresis.pressure_friction = read.Number(kHysteresisPressureFriction, 0.0);
  if (const auto problem = physics::hysteresis_problem(result.hysteresis); read.ok() && problem) {
    static constexpr std::string_view kAttribute[] = {kHysteresis, kHysteresisFriction, kHysteresisPressureFriction,
                                                      kHysteresisLength};
    read.Fail(kAttribute[static_cast<int>(problem->field)], problem->requirement);
  }
  if (!read.ok()) return std::nullopt;
  result.planar = ReadPlanarPath(read);
  if (!read.ok()) return std::nullopt;
  return result;
}

std::string FpamConfig::ToText() const {
  std::string text = fmt::format("{} {}={:.10g}", kPluginName, kRestLength, law.rest_length);
  const auto& rows = law.fpam.rows();
  if (law.fpam.is_constant()) {
    text += fmt::format(" {}={:.10g} {}={:.10g}", kRadius, rows[0].radius, kMaxContraction, rows[0].max_contraction);
  } else {
    std::vector<double> pressures_kpa, radii, max_contractions;
    for (const auto& row : rows) {
      pressures_kpa.push_back(units::pa_to_kpa(row.pressure));
      radii.push_back(row.radius);
      max_contractions.push_back(row.max_contraction);
    }
    text += fmt::format(" {}={} {}={} {}={}", kTablePressureKpa, list(pressures_kpa), kTableRadius, list(radii),
                        kTableMaxContraction, list(max_contractions));
  }
  const auto& fabric = law.fpam.fabric();
  text += fmt::format(" {}={:.10g} {}={:.10g} {}={:.10g}", kElasticModulus, fabric.elastic_modulus, kThickness,
                      fabric.thickness, kElasticOnset, fabric.elastic_onset_contraction);
  if (fabric.elastic_curvature > 0.0) text += fmt::format(" {}={:.10g}", kElasticCurvature, fabric.elastic_curvature);
  text += fmt::format(" {}={}", kStretch, physics::to_string(law.stretch_mode));
  if (law.stretch_mode != physics::StretchMode::kNone) {
    text += fmt::format(" {}={:.10g} {}={:.10g}", kForearmStiffness, law.mount_stiffness.forearm, kHandStiffness,
                        law.mount_stiffness.hand);
    const physics::MountStiffness& k = law.mount_stiffness;  // its shape as read, whatever the share
    if (!k.has_papers_shape())
      text += fmt::format(" {}={:.10g} {}={:.10g}", kMountExponent, k.exponent, kMountPreload, k.preload);
    if (k.shaped_share != 1.0) text += fmt::format(" {}={:.10g}", kMountShapedShare, k.shaped_share);
  }
  text +=
      fmt::format(" {}={:.10g} {}={:.10g}", kMaxPressureKpa, max_pressure_kpa, kTimeConstant, regulator.time_constant);
  if (regulator.vent_time_constant > 0.0)
    text += fmt::format(" {}={:.10g}", kVentTimeConstant, regulator.vent_time_constant);
  if (regulator.second_order_time > 0.0)
    text += fmt::format(" {}={:.10g}", kSecondOrderTime, regulator.second_order_time);
  if (hysteresis.active()) {
    text += fmt::format(" {}={:.10g} {}={:.10g} {}={:.10g} {}={:.10g}", kHysteresis, hysteresis.fraction,
                        kHysteresisLength, hysteresis.transition_length, kHysteresisFriction, hysteresis.friction_force,
                        kHysteresisPressureFriction, hysteresis.pressure_friction);
  }
  if (planar) {
    const auto& p = planar->placement;
    const auto& surface = planar->surface;
    text += fmt::format(" {}=planar {}={} {}={:.10g}", kRouting, kPlacement, list({p.d1, p.w1, p.d2, p.w2}),
                        kWristRadius, planar->wrist_radius);
    if (!surface.is_papers()) text += fmt::format(" {}={}", kWrapSurface, list({surface.x, surface.y, surface.aspect}));
  }
  return text;
}

}  // namespace softwrist::plugin
