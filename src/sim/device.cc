#include "sim/device.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "io/json_reader.h"
#include "io/text_file.h"
#include "physics/errors.h"
#include "physics/exosuit_layout.h"
#include "physics/paper_parameters.h"
#include "physics/plausible_ranges.h"
#include "physics/torque_geometry.h"

namespace softwrist::sim {
namespace {

using nlohmann::json;
using units::cm_to_m;
using units::m_to_cm;

constexpr const char* kFormat = "softwrist.placement/1";

using Reader = io::JsonReader;

// The fabric's hysteresis (physics/fpam_hysteresis.h): optional fields of "fpam", none unless given.
physics::FpamHysteresis read_hysteresis(Reader& fpam) {
  physics::FpamHysteresis h;
  h.fraction = fpam.number("hysteresis", h.fraction);
  h.transition_length = units::mm_to_m(fpam.positive("hysteresis_length_mm", units::m_to_mm(h.transition_length)));
  h.friction_force = fpam.number("hysteresis_friction_n", h.friction_force);
  h.pressure_friction = fpam.number("hysteresis_pressure_friction", h.pressure_friction);
  if (const auto problem = physics::hysteresis_problem(h)) {
    static constexpr const char* kField[] = {"hysteresis", "hysteresis_friction_n", "hysteresis_pressure_friction",
                                             "hysteresis_length_mm"};
    fpam.fail(kField[static_cast<int>(problem->field)],
              fmt::format("{}, got {}", problem->requirement, problem->value));
  }
  return h;
}

// The fabric of Eqn. force's elastic term: optional "fabric" of "fpam", the paper's (FabricProperties' defaults)
// unless given.
physics::FabricProperties read_fabric(Reader& fpam) {
  physics::FabricProperties fabric;
  if (!fpam.has("fabric")) return fabric;
  Reader f = fpam.child("fabric");
  fabric.elastic_modulus = f.positive("elastic_modulus_mpa", fabric.elastic_modulus / 1e6) * 1e6;
  fabric.thickness = units::mm_to_m(f.positive("thickness_mm", units::m_to_mm(fabric.thickness)));
  fabric.elastic_onset_contraction = f.number("elastic_onset", fabric.elastic_onset_contraction);
  fabric.elastic_curvature = f.number("elastic_curvature", fabric.elastic_curvature);
  try {
    physics::validate(fabric);
  } catch (const physics::InvalidParameter& e) {
    f.fail("", e.what());
  }
  f.finish();
  return fabric;
}

physics::FpamParameters read_fpam(Reader fpam, physics::FpamHysteresis& hysteresis) {
  hysteresis = read_hysteresis(fpam);
  const physics::FabricProperties fabric = read_fabric(fpam);
  if (fpam.has("table")) {
    const json& table = fpam.raw("table");
    if (!table.is_array() || table.empty()) fpam.fail("table", "must be a non-empty array of rows");
    std::vector<physics::FpamTableRow> rows;
    for (std::size_t i = 0; i < table.size(); ++i) {
      Reader row(table[i], fpam.source(), fmt::format("{}.table[{}]", fpam.path(), i));
      rows.push_back(
          {units::kpa_to_pa(row.number("pressure_kpa")), cm_to_m(row.number("r0_cm")), row.number("eps_max")});
      row.finish();
    }
    fpam.finish();
    try {
      return physics::FpamParameters::Table(rows, fabric);
    } catch (const physics::InvalidParameter& e) {
      fpam.fail("table", e.what());
    }
  }
  const double r0 = cm_to_m(fpam.number("r0_cm"));
  const double eps_max = fpam.number("eps_max");
  fpam.finish();
  try {
    return physics::FpamParameters::Constant(r0, eps_max, fabric);
  } catch (const physics::InvalidParameter& e) {
    fpam.fail("", e.what());
  }
}

json fpam_to_json(const physics::FpamParameters& fpam) {
  json out;
  if (fpam.is_constant()) {
    out = {{"r0_cm", m_to_cm(fpam.rows().front().radius)}, {"eps_max", fpam.rows().front().max_contraction}};
  } else {
    json rows = json::array();
    for (const auto& row : fpam.rows()) {
      rows.push_back({{"pressure_kpa", units::pa_to_kpa(row.pressure)},
                      {"r0_cm", m_to_cm(row.radius)},
                      {"eps_max", row.max_contraction}});
    }
    out = {{"table", rows}};
  }
  // Only a fabric other than the paper's: every placement file so far has none (and the replays' caches key on it).
  const physics::FabricProperties& fabric = fpam.fabric();
  if (!(fabric == physics::FabricProperties{})) {
    out["fabric"] = {{"elastic_modulus_mpa", fabric.elastic_modulus / 1e6},
                     {"thickness_mm", units::m_to_mm(fabric.thickness)},
                     {"elastic_onset", fabric.elastic_onset_contraction},
                     {"elastic_curvature", fabric.elastic_curvature}};
  }
  return out;
}

}  // namespace

std::optional<MuscleIndex> muscle_from_name(std::string_view name) {
  for (std::size_t i = 0; i < kMuscleNames.size(); ++i) {
    if (name == kMuscleNames[i]) return static_cast<MuscleIndex>(i);
  }
  return std::nullopt;
}

const char* to_string(Routing routing) { return routing == Routing::kPlanar ? "planar" : "spatial"; }

std::optional<Routing> parse_routing(std::string_view text) {
  if (text == "spatial") return Routing::kSpatial;
  if (text == "planar") return Routing::kPlanar;
  return std::nullopt;
}

physics::Muscle DeviceDescription::muscle(int index) const {
  const MuscleMount& mount = muscles.at(static_cast<std::size_t>(index));
  return physics::Muscle{muscle_law(mount), mount.placement, mount.wrist_radius, mount.wrap_surface};
}

physics::FpamParameters DeviceDescription::fpam_of(const MuscleMount& mount) const {
  if (mount.fpam_radius_scale == 1.0 && mount.fpam_max_contraction_shift == 0.0) return fpam;
  return fpam.scaled(mount.fpam_radius_scale, mount.fpam_max_contraction_shift);
}

physics::MuscleLaw DeviceDescription::muscle_law(const MuscleMount& mount) const {
  return {.fpam = fpam_of(mount),
          .rest_length = mount.rest_length,
          .stretch_mode = stretch_mode,
          .mount_stiffness = mount_stiffness};
}

DeviceDescription paper_device() {
  const auto flexor = physics::paper::torque_measurement_flexor(physics::StretchMode::kSelfConsistent);
  DeviceDescription device{.muscles = {}, .fpam = physics::paper::tensile_fpam()};
  device.muscles[kFlexor] = {flexor.placement, flexor.rest_length, flexor.wrist_radius};
  const auto& rom = physics::paper::rom_table();
  for (int i : {kExtensor, kUlnar, kRadial}) {
    device.muscles[static_cast<std::size_t>(i)] = {rom[static_cast<std::size_t>(i)].placement,
                                                   rom[static_cast<std::size_t>(i)].rest_length,
                                                   physics::paper::kRomWristRadius};
  }
  device.stretch_mode = physics::StretchMode::kSelfConsistent;
  device.mount_stiffness = flexor.mount_stiffness;
  return device;
}

namespace {

// The four muscles' mounts, each checked against the device's fPAM.
void read_muscle_mounts(Reader muscles, DeviceDescription& device) {
  for (std::size_t i = 0; i < kMuscleNames.size(); ++i) {
    Reader m = muscles.child(kMuscleNames[i]);
    MuscleMount& mount = device.muscles[i];
    mount.placement = {cm_to_m(m.number("d1_cm")), cm_to_m(m.number("w1_cm")), cm_to_m(m.number("d2_cm")),
                       cm_to_m(m.number("w2_cm"))};
    mount.rest_length = cm_to_m(m.number("L0_cm"));
    mount.wrist_radius = cm_to_m(m.number("rw_cm"));
    mount.wrap_surface = {cm_to_m(m.number("wrap_centre_x_cm", 0.0)), cm_to_m(m.number("wrap_centre_y_cm", 0.0)),
                          m.number("wrap_aspect", 1.0)};
    mount.fpam_radius_scale = m.positive("r0_scale", 1.0);
    mount.fpam_max_contraction_shift = m.number("eps_max_shift", 0.0);
    m.finish();
    try {
      physics::validate(physics::Muscle{{.fpam = device.fpam_of(mount), .rest_length = mount.rest_length},
                                        mount.placement,
                                        mount.wrist_radius,
                                        mount.wrap_surface});
    } catch (const physics::InvalidParameter& e) {
      m.fail("", e.what());
    }
  }
  muscles.finish();
}

void read_stretch(Reader stretch, DeviceDescription& device) {
  const std::string mode = stretch.text("mode", "none");
  const auto parsed = physics::parse_stretch_mode(mode);
  if (!parsed) stretch.fail("mode", fmt::format("'{}' is not none, oneshot or selfconsistent", mode));
  device.stretch_mode = *parsed;
  device.mount_stiffness = {.forearm = units::n_per_cm2_to_n_per_m2(stretch.number("K1_n_per_cm2", 0.0)),
                            .hand = units::n_per_cm2_to_n_per_m2(stretch.number("K2_n_per_cm2", 0.0)),
                            .exponent = stretch.number("exponent", 2.0),
                            .preload = stretch.number("preload_n", 0.0),
                            .shaped_share = stretch.number("shaped_share", 1.0)};
  try {
    if (device.stretch_mode != physics::StretchMode::kNone) physics::validate(device.mount_stiffness);
    physics::validate_shape(device.mount_stiffness);  // whatever the mode: it is written back as read
  } catch (const physics::InvalidParameter& e) {
    stretch.fail("", e.what());
  }
  stretch.finish();
}

void read_regulator(Reader r, Regulator& regulator) {
  regulator.max_pressure = units::kpa_to_pa(r.positive("max_pressure_kpa", physics::kRegulatorMaxPressureKpa));
  if (regulator.max_pressure > physics::plausible::kMaxPressure) {
    r.fail("max_pressure_kpa", "must be at most 1000 (10 bar, far above a fabric muscle's burst pressure)");
  }
  regulator.time_constant = r.positive("time_constant_s", regulator.time_constant);
  if (regulator.time_constant < physics::plausible::kMinTimeConstant ||
      regulator.time_constant > physics::plausible::kMaxTimeConstant) {
    r.fail("time_constant_s", "must lie in [0.001, 100] (the model integrates it in 1 ms steps)");
  }
  regulator.vent_time_constant = r.non_negative("vent_time_constant_s", 0.0);  // 0: as time_constant_s
  if (regulator.vent_time_constant != 0.0 && (regulator.vent_time_constant < physics::plausible::kMinTimeConstant ||
                                              regulator.vent_time_constant > physics::plausible::kMaxTimeConstant)) {
    r.fail("vent_time_constant_s", "must be 0 (as time_constant_s) or lie in [0.001, 100] (1 ms integration steps)");
  }
  if (regulator.vent_time_constant == regulator.time_constant) regulator.vent_time_constant = 0.0;
  regulator.second_order_time = r.non_negative("second_order_time_s", 0.0);  // 0: first order
  if (regulator.second_order_time > physics::plausible::kMaxTimeConstant) {
    r.fail("second_order_time_s", "must lie in [0, 100] (0: a first-order regulator)");
  }
  r.finish();
}

void read_wrist(Reader w, PassiveWrist& p) {
  p.stiffness_fe = w.number("stiffness_fe_nm_per_rad", p.stiffness_fe);
  p.stiffness_ur = w.number("stiffness_ur_nm_per_rad", p.stiffness_ur);
  p.damping_fe = w.number("damping_fe_nms_per_rad", p.damping_fe);
  p.damping_ur = w.number("damping_ur_nms_per_rad", p.damping_ur);
  for (auto [key, value] : {std::pair{"stiffness_fe_nm_per_rad", p.stiffness_fe},
                            {"stiffness_ur_nm_per_rad", p.stiffness_ur},
                            {"damping_fe_nms_per_rad", p.damping_fe},
                            {"damping_ur_nms_per_rad", p.damping_ur}}) {
    if (value < 0.0) w.fail(key, fmt::format("must be >= 0, got {}", value));
  }
  p.flexion_limit = units::deg_to_rad(w.positive("flexion_limit_deg", units::rad_to_deg(p.flexion_limit)));
  p.extension_limit = units::deg_to_rad(w.positive("extension_limit_deg", units::rad_to_deg(p.extension_limit)));
  p.ulnar_limit = units::deg_to_rad(w.positive("ulnar_limit_deg", units::rad_to_deg(p.ulnar_limit)));
  p.radial_limit = units::deg_to_rad(w.positive("radial_limit_deg", units::rad_to_deg(p.radial_limit)));
  for (auto [key, value] : {std::pair{"stiffness_asymmetry_fe", &p.stiffness_asymmetry_fe},
                            {"stiffness_asymmetry_ur", &p.stiffness_asymmetry_ur}}) {
    *value = w.number(key, *value);
    if (!(std::abs(*value) <= physics::kMaxStiffnessAsymmetry))
      w.fail(key, fmt::format("must lie in [-{0}, {0}], got {1}", physics::kMaxStiffnessAsymmetry, *value));
  }
  p.limit_stiffening.torque = w.number("limit_stiffening_nm", p.limit_stiffening.torque);
  // Bounds that keep the 1 ms explicit step of WristSim stable (sqrt((A/s)/I) dt < 0.3 for a hand of 0.003 kg m^2)
  // and cover a relaxed wrist's passive torque at its limits (a few N m).
  if (p.limit_stiffening.torque < 0.0 || p.limit_stiffening.torque > 20.0) {
    w.fail("limit_stiffening_nm", fmt::format("must lie in [0, 20] N m, got {}", p.limit_stiffening.torque));
  }
  const double scale_deg = w.positive("limit_stiffening_scale_deg", units::rad_to_deg(p.limit_stiffening.angle_scale));
  if (scale_deg < 4.0) w.fail("limit_stiffening_scale_deg", fmt::format("must be at least 4 deg, got {}", scale_deg));
  p.limit_stiffening.angle_scale = units::deg_to_rad(scale_deg);
  w.finish();
}

void read_hand(Reader h, Hand& hand) {
  hand.mass = h.positive("mass_kg", hand.mass);
  hand.com_distance = cm_to_m(h.positive("com_distance_cm", m_to_cm(hand.com_distance)));
  hand.radius_of_gyration = cm_to_m(h.positive("radius_of_gyration_cm", m_to_cm(hand.radius_of_gyration)));
  hand.length = cm_to_m(h.positive("length_cm", m_to_cm(hand.length)));
  h.finish();
}

// The regulator's entry of a placement file; the venting time constant only where it differs, the second order only
// where there is one.
nlohmann::json regulator_json(const Regulator& regulator) {
  nlohmann::json j = {{"max_pressure_kpa", units::pa_to_kpa(regulator.max_pressure)},
                      {"time_constant_s", regulator.time_constant}};
  if (regulator.vent_time_constant > 0.0) j["vent_time_constant_s"] = regulator.vent_time_constant;
  if (regulator.second_order_time > 0.0) j["second_order_time_s"] = regulator.second_order_time;
  return j;
}

}  // namespace

DeviceDescription parse_device(const std::string& json_text, const std::string& source_name) {
  const json root = io::parse_json(json_text, source_name);
  Reader top(root, source_name, "");
  if (const std::string format = top.text("format", kFormat); format != kFormat) {
    top.fail("format", fmt::format("'{}' is not '{}'", format, kFormat));
  }
  physics::FpamHysteresis hysteresis;
  DeviceDescription device{.muscles = {}, .fpam = read_fpam(top.child("fpam"), hysteresis)};
  device.hysteresis = hysteresis;
  read_muscle_mounts(top.child("muscles"), device);
  const std::string routing = top.text("routing", to_string(Routing::kSpatial));
  if (const auto parsed = parse_routing(routing)) {
    device.routing = *parsed;
  } else {
    top.fail("routing", fmt::format("'{}' is not spatial or planar", routing));
  }
  if (top.has("stretch")) read_stretch(top.child("stretch"), device);
  if (top.has("regulator")) read_regulator(top.child("regulator"), device.regulator);
  if (top.has("wrist")) read_wrist(top.child("wrist"), device.wrist);
  if (top.has("hand")) read_hand(top.child("hand"), device.hand);
  try {
    check_hand_mount_clearance(device);  // against the wrist's range, read last
  } catch (const physics::InvalidParameter& e) {
    top.fail("muscles", e.what());
  }
  top.finish();
  return device;
}

double muscle_reach(const DeviceDescription& device, int index) {
  const PassiveWrist& w = device.wrist;
  const bool fe = index == kFlexor || index == physics::kExtensor;
  return (fe ? std::max(w.flexion_limit, w.extension_limit) : std::max(w.ulnar_limit, w.radial_limit)) +
         units::deg_to_rad(15.0);
}

void check_hand_mount_clearance(const DeviceDescription& device) {
  for (std::size_t i = 0; i < device.muscles.size(); ++i) {
    const MuscleMount& m = device.muscles[i];
    if (m.wrap_surface.is_papers()) continue;  // R2 > r_w at every angle (physics::validate)
    const double reach = muscle_reach(device, static_cast<int>(i));
    const double clearance = physics::hand_mount_clearance(m.placement, m.wrist_radius, m.wrap_surface, reach);
    if (!(clearance > 1.0)) {
      throw physics::InvalidParameter(fmt::format(
          "{}: the hand mount comes inside the wrist surface within +-{:.1f} deg of the joint's zero (its least "
          "scaled distance from the surface's centre {:.4g}, must exceed 1)",
          kMuscleNames[i], units::rad_to_deg(reach), clearance));
    }
  }
}

DeviceDescription rom_device() {
  DeviceDescription device{.muscles = {}, .fpam = physics::paper::rom_fpam()};
  for (std::size_t i = 0; i < device.muscles.size(); ++i) {
    const auto& entry = physics::paper::rom_table()[i];
    device.muscles[i] = {entry.placement, entry.rest_length, physics::paper::kRomWristRadius};
  }
  device.stretch_mode = physics::StretchMode::kSelfConsistent;
  device.mount_stiffness =
      physics::paper::torque_measurement_flexor(physics::StretchMode::kSelfConsistent).mount_stiffness;
  return device;
}

DeviceDescription load_device(const std::filesystem::path& path) {
  return parse_device(io::read_text_file(path), path.string());
}

std::string device_to_json(const DeviceDescription& device) {
  json muscles;
  for (std::size_t i = 0; i < kMuscleNames.size(); ++i) {
    const auto& m = device.muscles[i];
    muscles[kMuscleNames[i]] = {{"d1_cm", m_to_cm(m.placement.d1)}, {"w1_cm", m_to_cm(m.placement.w1)},
                                {"d2_cm", m_to_cm(m.placement.d2)}, {"w2_cm", m_to_cm(m.placement.w2)},
                                {"L0_cm", m_to_cm(m.rest_length)},  {"rw_cm", m_to_cm(m.wrist_radius)}};
    if (!m.wrap_surface.at_joint()) {  // the paper's circle about the joint unless moved
      muscles[kMuscleNames[i]]["wrap_centre_x_cm"] = m_to_cm(m.wrap_surface.x);
      muscles[kMuscleNames[i]]["wrap_centre_y_cm"] = m_to_cm(m.wrap_surface.y);
    }
    if (!m.wrap_surface.circular()) muscles[kMuscleNames[i]]["wrap_aspect"] = m.wrap_surface.aspect;
    if (m.fpam_radius_scale != 1.0) muscles[kMuscleNames[i]]["r0_scale"] = m.fpam_radius_scale;
    if (m.fpam_max_contraction_shift != 0.0) muscles[kMuscleNames[i]]["eps_max_shift"] = m.fpam_max_contraction_shift;
  }
  const auto& w = device.wrist;
  json stretch = {{"mode", physics::to_string(device.stretch_mode)},
                  {"K1_n_per_cm2", units::n_per_m2_to_n_per_cm2(device.mount_stiffness.forearm)},
                  {"K2_n_per_cm2", units::n_per_m2_to_n_per_cm2(device.mount_stiffness.hand)}};
  // The shape as read (a share of 0 makes it the paper's law whatever the shape, but it is written back as read).
  const physics::MountStiffness& k = device.mount_stiffness;
  if (!k.has_papers_shape()) {
    stretch["exponent"] = k.exponent;
    stretch["preload_n"] = k.preload;
  }
  if (k.shaped_share != 1.0) stretch["shaped_share"] = k.shaped_share;
  json root = {
      {"format", kFormat},
      {"muscles", muscles},
      {"fpam", fpam_to_json(device.fpam)},
      {"stretch", stretch},
      {"regulator", regulator_json(device.regulator)},
      {"wrist",
       {{"stiffness_fe_nm_per_rad", w.stiffness_fe},
        {"stiffness_ur_nm_per_rad", w.stiffness_ur},
        {"damping_fe_nms_per_rad", w.damping_fe},
        {"damping_ur_nms_per_rad", w.damping_ur},
        {"flexion_limit_deg", units::rad_to_deg(w.flexion_limit)},
        {"extension_limit_deg", units::rad_to_deg(w.extension_limit)},
        {"ulnar_limit_deg", units::rad_to_deg(w.ulnar_limit)},
        {"radial_limit_deg", units::rad_to_deg(w.radial_limit)}}},
      {"hand",
       {{"mass_kg", device.hand.mass},
        {"com_distance_cm", m_to_cm(device.hand.com_distance)},
        {"radius_of_gyration_cm", m_to_cm(device.hand.radius_of_gyration)},
        {"length_cm", m_to_cm(device.hand.length)}}},
  };
  if (device.routing != Routing::kSpatial) root["routing"] = to_string(device.routing);
  if (device.hysteresis.active()) {  // only where the fabric is not the paper's static one
    root["fpam"]["hysteresis"] = device.hysteresis.fraction;
    root["fpam"]["hysteresis_length_mm"] = units::m_to_mm(device.hysteresis.transition_length);
    root["fpam"]["hysteresis_friction_n"] = device.hysteresis.friction_force;
    root["fpam"]["hysteresis_pressure_friction"] = device.hysteresis.pressure_friction;
  }
  if (w.stiffness_asymmetry_fe != 0.0 || w.stiffness_asymmetry_ur != 0.0) {  // likewise
    root["wrist"]["stiffness_asymmetry_fe"] = w.stiffness_asymmetry_fe;
    root["wrist"]["stiffness_asymmetry_ur"] = w.stiffness_asymmetry_ur;
  }
  if (w.limit_stiffening.torque > 0.0) {  // only where the wrist is not the paper's linear one
    root["wrist"]["limit_stiffening_nm"] = w.limit_stiffening.torque;
    root["wrist"]["limit_stiffening_scale_deg"] = units::rad_to_deg(w.limit_stiffening.angle_scale);
  }
  return root.dump(2) + "\n";
}

}  // namespace softwrist::sim
