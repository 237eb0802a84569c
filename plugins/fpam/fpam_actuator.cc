#include "fpam_actuator.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <vector>

#include "physics/errors.h"
#include "physics/fpam_force.h"
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
      *error_ = "actuator '" + std::string(actuator_) + "': " +
                (key.empty() ? std::string() : "attribute '" + std::string(key) + "': ") + problem;
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
  fabric.elastic_modulus = read.Positive(FpamActuator::kElasticModulus, fabric.elastic_modulus);
  fabric.thickness = read.Positive(FpamActuator::kThickness, fabric.thickness);
  fabric.elastic_onset_contraction = read.Number(FpamActuator::kElasticOnset, fabric.elastic_onset_contraction);
  if (!read.ok()) return std::nullopt;
  const bool constant = read.Has(FpamActuator::kRadius) || read.Has(FpamActuator::kMaxContraction);
  const bool table = read.Has(FpamActuator::kTablePressureKpa) || read.Has(FpamActuator::kTableRadius) ||
                     read.Has(FpamActuator::kTableMaxContraction);
  if (constant == table) {
    read.Fail("", "give either r0 and eps_max, or table_pressure_kpa, table_r0 and table_eps_max");
    return std::nullopt;
  }
  try {
    if (constant) {
      const double r0 = read.Number(FpamActuator::kRadius);
      const double eps_max = read.Number(FpamActuator::kMaxContraction);
      if (!read.ok()) return std::nullopt;
      return physics::FpamParameters::Constant(r0, eps_max, fabric);
    }
    const auto pressures = read.Numbers(FpamActuator::kTablePressureKpa);
    const auto radii = read.Numbers(FpamActuator::kTableRadius);
    const auto eps = read.Numbers(FpamActuator::kTableMaxContraction);
    if (!read.ok()) return std::nullopt;
    if (radii.size() != pressures.size() || eps.size() != pressures.size()) {
      read.Fail(FpamActuator::kTablePressureKpa, "table_pressure_kpa, table_r0 and table_eps_max differ in length");
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

}  // namespace

std::optional<FpamActuator> FpamActuator::Create(const PluginConfig& config, std::string_view actuator_name,
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
  FpamActuator actuator(std::move(*fpam));
  if (read.Has(kRestLength)) {
    actuator.rest_length_ = read.Positive(kRestLength, 0.0);
    if (read.ok() && actuator.rest_length_ > physics::plausible::kMaxLength) read.Fail(kRestLength, "must be at most 10 m");
  } else {
    read.Fail(kRestLength, "missing");
  }
  const std::string stretch = read.Text(kStretch, "none");
  const auto mode = physics::parse_stretch_mode(stretch);
  if (!mode) read.Fail(kStretch, "'" + stretch + "' is not none, oneshot or selfconsistent");
  actuator.stretch_mode_ = mode.value_or(physics::StretchMode::kNone);
  actuator.mount_stiffness_ = {read.Number(kForearmStiffness, 0.0), read.Number(kHandStiffness, 0.0)};
  if (read.ok() && actuator.stretch_mode_ != physics::StretchMode::kNone) {
    if (actuator.mount_stiffness_.forearm == 0.0) read.Fail(kForearmStiffness, "must be given and non-zero");
    if (actuator.mount_stiffness_.hand == 0.0) read.Fail(kHandStiffness, "must be given and non-zero");
  }
  actuator.max_pressure_kpa_ = read.Positive(kMaxPressureKpa, actuator.max_pressure_kpa_);
  if (read.ok() && actuator.max_pressure_kpa_ > units::pa_to_kpa(physics::plausible::kMaxPressure)) {
    read.Fail(kMaxPressureKpa, "must be at most 1000 (kPa)");
  }
  actuator.time_constant_ = read.Positive(kTimeConstant, actuator.time_constant_);
  if (read.ok() && !(actuator.time_constant_ >= physics::plausible::kMinTimeConstant &&
                     actuator.time_constant_ <= physics::plausible::kMaxTimeConstant)) {
    read.Fail(kTimeConstant, "must lie in [0.001, 100] (s; MuJoCo integrates the regulator in 1 ms steps)");
  }
  if (!read.ok()) return std::nullopt;
  return actuator;
}

double FpamActuator::PressureRate(double commanded_kpa, double regulated_kpa) const {
  if (!std::isfinite(commanded_kpa) || !std::isfinite(regulated_kpa)) return 0.0;
  return (std::clamp(commanded_kpa, 0.0, max_pressure_kpa_) - regulated_kpa) / time_constant_;
}

double FpamActuator::Force(double tendon_length, double regulated_kpa) const {
  if (!std::isfinite(tendon_length) || !std::isfinite(regulated_kpa) || tendon_length < 0.0) return 0.0;
  const double pressure = units::kpa_to_pa(std::clamp(regulated_kpa, 0.0, max_pressure_kpa_));
  const physics::FpamForceLaw force_law(pressure, fpam_.at_pressure(pressure), fpam_.fabric());
  const double rest_length = rest_length_;
  // Eqn. force's contraction ratio, (L0 - L) / L0; L0 > 0 was validated in Create.
  const auto force_at_length = [&](double length) { return force_law((rest_length - length) / rest_length); };
  return physics::solve_mount_stretch(force_at_length, tendon_length, mount_stiffness_, stretch_mode_).force;
}

}  // namespace softwrist::plugin
