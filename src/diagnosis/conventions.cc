#include "diagnosis/conventions.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "io/json_reader.h"
#include "physics/units.h"

namespace softwrist::diagnosis {
namespace {

constexpr std::array<std::pair<Posture, const char*>, 3> kPostures = {{
    {Posture::kHandSupported, "hand_supported"},
    {Posture::kGravityFe, "gravity_fe"},
    {Posture::kGravityUr, "gravity_ur"},
}};

// The coarsest angle sensor step that is still a measurement of a wrist angle.
constexpr double kMaxAngleResolutionDeg = 5.0;

}  // namespace

const char* to_string(Posture posture) {
  for (const auto& [p, name] : kPostures) {
    if (p == posture) return name;
  }
  return "?";
}

std::optional<Posture> posture_from_name(const std::string& name) {
  for (const auto& [p, n] : kPostures) {
    if (name == n) return p;
  }
  return std::nullopt;
}

std::optional<physics::WristAxis> gravity_axis(Posture posture) {
  switch (posture) {
    case Posture::kGravityFe:
      return physics::WristAxis::kFlexionExtension;
    case Posture::kGravityUr:
      return physics::WristAxis::kUlnarRadial;
    case Posture::kHandSupported:
      break;
  }
  return std::nullopt;
}

std::optional<TorqueIncludes> torque_includes_from_name(const std::string& name) {
  if (name == "baseline_subtracted") return TorqueIncludes{.baseline_subtracted = true};
  std::vector<std::string> terms;  // empty ones too: "muscle+" is not a name
  for (std::size_t start = 0;;) {
    const std::size_t plus = name.find('+', start);
    terms.push_back(name.substr(start, plus == std::string::npos ? std::string::npos : plus - start));
    if (plus == std::string::npos) break;
    start = plus + 1;
  }
  if (std::count(terms.begin(), terms.end(), "muscle") != 1) return std::nullopt;
  TorqueIncludes includes;
  for (const std::string& term : terms) {
    bool* flag = term == "passive_wrist" ? &includes.passive_wrist
                 : term == "hand_weight" ? &includes.hand_weight
                                         : nullptr;
    if (term == "muscle") continue;
    if (flag == nullptr || *flag) return std::nullopt;  // unknown or repeated
    *flag = true;
  }
  return includes;
}

std::string to_string(const TorqueIncludes& includes) {
  if (includes.baseline_subtracted) return "baseline_subtracted";
  std::string name = "muscle";
  if (includes.passive_wrist) name += "+passive_wrist";
  if (includes.hand_weight) name += "+hand_weight";
  return name;
}

Conventions conventions_from_config(const nlohmann::json& config, const std::filesystem::path& log_dir,
                                    const std::string& source) {
  Conventions c;
  if (!config.is_object()) return c;
  io::JsonReader reader(config, source, "config");
  if (reader.boolean("hand_supported", false)) c.posture = Posture::kHandSupported;
  if (reader.has("posture")) {
    const std::string name = reader.text("posture");
    const auto posture = posture_from_name(name);
    if (!posture) reader.fail("posture", fmt::format("'{}' is not hand_supported, gravity_fe or gravity_ur", name));
    if (reader.boolean("hand_supported", false) && *posture != Posture::kHandSupported)
      reader.fail("posture", fmt::format("'{}' contradicts hand_supported: true", name));
    c.posture = *posture;
  }
  if (reader.has("torque_includes")) {
    const std::string name = reader.text("torque_includes");
    const auto includes = torque_includes_from_name(name);
    if (!includes) {
      reader.fail("torque_includes", fmt::format("'{}' is not muscle, muscle+passive_wrist, muscle+hand_weight, "
                                                 "muscle+passive_wrist+hand_weight or baseline_subtracted",
                                                 name));
    }
    c.torque = *includes;
  }
  c.angles_zeroed_at_start = reader.boolean("angles_zeroed_at_start", false);
  const double resolution_deg = reader.non_negative("angle_resolution_deg", 0.0);
  if (resolution_deg > kMaxAngleResolutionDeg)
    reader.fail("angle_resolution_deg",
                fmt::format("{} deg is coarser than {} deg", resolution_deg, kMaxAngleResolutionDeg));
  c.angle_resolution = units::deg_to_rad(resolution_deg);
  if (reader.has("placement")) {
    const std::filesystem::path placement = reader.text("placement");
    if (placement.empty()) reader.fail("placement", "is empty");
    c.placement = placement.is_absolute() ? placement : log_dir / placement;
    if (!std::filesystem::is_regular_file(c.placement))
      reader.fail("placement", fmt::format("{} is not a file", c.placement.string()));
  }
  return c;
}

void write_conventions(const Conventions& c, nlohmann::json& config) {
  if (c.posture == Posture::kHandSupported) config["hand_supported"] = true;
  config["posture"] = to_string(c.posture);
  if (c.torque != TorqueIncludes{}) config["torque_includes"] = to_string(c.torque);
  if (c.angles_zeroed_at_start) config["angles_zeroed_at_start"] = true;
  if (c.angle_resolution > 0.0) config["angle_resolution_deg"] = units::rad_to_deg(c.angle_resolution);
  if (!c.placement.empty()) config["placement"] = c.placement.string();
}

}  // namespace softwrist::diagnosis
