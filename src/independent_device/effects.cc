#include "independent_device/effects.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "independent_device/units.h"

namespace softwrist::independent {
namespace {

// Muscles on a body (with mounts and a wrap): the rig's flexor and the prototype's four.
template <typename F>
void for_mounted(DeviceSpec& d, F&& f) {
  f(d.rig_flexor);
  for (auto& m : d.prototype) f(m);
}
// Every fPAM, the tensile specimen included.
template <typename F>
void for_all(DeviceSpec& d, F&& f) {
  f(d.tensile_specimen);
  for_mounted(d, f);
}

using ApplyEffect = void (*)(DeviceSpec& device, double level, nlohmann::json& parameters);

void add_form(std::vector<EffectDefinition>& defs, const char* name, const char* label, const char* description,
              const char* parameter, double value, ApplyEffect apply) {
  defs.push_back({FormInfo{name, label, description, parameter, value}, apply});
}

void add_mount_stretch_forms(std::vector<EffectDefinition>& defs) {
  add_form(defs, "strap_linear_preload", "mount_stretch",
           "elbow-band strap in series with the mounts: a linear spring that gives only above an 8 N donning preload",
           "strap stiffness above the preload [N/m]", 4000.0, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_mounted(d, [&](MuscleSpec& m) { m.mount.strap_compliance_m_per_n = level / 4000.0; });
             p["strap_stiffness_n_per_m"] = 4000.0 / level;
             p["strap_preload_n"] = 8.0;
           });
  add_form(
      defs, "strap_stiffening", "mount_stretch",
      "J-curve strap and soft tissue in series with the mounts, F = 4 N (exp(dx/x_s) - 1) (Fung 1967): soft at low "
      "tension, stiffening",
      "J-curve length scale x_s [m]", 0.004, [](DeviceSpec& d, double level, nlohmann::json& p) {
        for_mounted(d, [&](MuscleSpec& m) { m.mount.jcurve_length_m = 0.004 * level; });
        p["jcurve_length_m"] = 0.004 * level;
        p["jcurve_force_n"] = 4.0;
      });
  add_form(defs, "glove_slide", "mount_stretch",
           "the glove shears over the hand towards the wrist in proportion to tension: the hand anchor moves (d2 "
           "shrinks), changing the moment arm as well as the length",
           "glove shear stiffness along the hand [N/m]", 5000.0, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_mounted(d, [&](MuscleSpec& m) { m.mount.glove_slide_m_per_n = level / 5000.0; });
             p["glove_shear_stiffness_n_per_m"] = 5000.0 / level;
           });
}

void add_fpam_params_forms(std::vector<EffectDefinition>& defs) {
  add_form(defs, "aged_fabric", "fpam_params",
           "aged, crept fabric: fully stretched radius +4 % and a maximum contraction lowered in proportion to "
           "pressure",
           "drop of the maximum contraction at 137 kPa", 0.03, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_all(d, [&](MuscleSpec& m) {
               m.law.aged_radius_gain = 0.04 * level;
               m.law.aged_contraction_drop_at_max = 0.03 * level;
             });
             p["radius_gain"] = 0.04 * level;
             p["max_contraction_drop_at_137_kpa"] = 0.03 * level;
           });
  add_form(defs, "tondu_end_effect", "fpam_params",
           "Tondu-Lopez law with an end-effect factor k: F = pi r0^2 P (a (1 - k e)^2 - b); the tied ends shorten the "
           "stroke and steepen the force-contraction curve",
           "end-effect factor k", 1.15, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_all(d, [&](MuscleSpec& m) { m.law.tondu_end_factor = 1.0 + 0.15 * level; });
             p["tondu_end_factor"] = 1.0 + 0.15 * level;
           });
  add_form(defs, "exponential_fabric", "fpam_params",
           "J-shaped fabric elasticity (the paper's own exponential fit at 0 kPa) on top of the linear term",
           "extra fabric force at full stretch (e = 0) [N]", 60.0, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_all(d, [&](MuscleSpec& m) { m.law.exponential_force_at_full_stretch_n = 60.0 * level; });
             p["extra_force_at_full_stretch_n"] = 60.0 * level;
             p["strain_scale"] = 0.03;
           });
}

void add_regulator_lag_forms(std::vector<EffectDefinition>& defs) {
  add_form(defs, "second_order_response", "regulator_lag",
           "the pressure follows the command through an underdamped second-order lag (zeta 0.3) after the nominal "
           "first-order one",
           "natural frequency [rad/s]", 3.0, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for (auto& r : d.regulators) {
               r.second_order_wn_rad_s = 3.0 / level;
               r.second_order_zeta = 0.3;
             }
             p["natural_frequency_rad_s"] = 3.0 / level;
             p["damping_ratio"] = 0.3;
           });
  add_form(defs, "slow_vent", "regulator_lag",
           "venting much slower than filling (subsonic exhaust flow at low gauge pressure)",
           "vent time constant added [s]", 3.0, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for (auto& r : d.regulators) {
               r.vent_tau_extra_s = 3.0 * level;
               r.fill_tau_extra_s = 0.3 * level;
             }
             p["vent_tau_added_s"] = 3.0 * level;
             p["fill_tau_added_s"] = 0.3 * level;
           });
  add_form(defs, "rate_limit_dead_time", "regulator_lag",
           "a slew-rate limit (choked supply flow) plus a dead time (tubing transport, valve dead band)",
           "dead time [s]", 0.1, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for (auto& r : d.regulators) {
               r.dead_time_s = 0.1 * level;
               r.rate_limit_kpa_per_s = 40.0 / level;
             }
             p["dead_time_s"] = 0.1 * level;
             p["rate_limit_kpa_per_s"] = 40.0 / level;
           });
}

void add_hysteresis_forms(std::vector<EffectDefinition>& defs) {
  add_form(
      defs, "dahl_friction", "hysteresis",
      "Dahl friction state in the fabric, Coulomb level 1.5 N + 0.08 pi r0^2 P, characteristic length 3 mm",
      "friction per unit of pi r0^2 P", 0.08, [](DeviceSpec& d, double level, nlohmann::json& p) {
        for_all(d, [&](MuscleSpec& m) { m.hysteresis = {HysteresisKind::dahl, 1.5 * level, 0.08 * level, 0.003}; });
        p["constant_n"] = 1.5 * level;
        p["pressure_fraction"] = 0.08 * level;
        p["length_m"] = 0.003;
      });
  add_form(defs, "maxwell_slip", "hysteresis",
           "Maxwell-slip elements (slip lengths 0.25-8 mm) with breakaway 1.5 N + 0.10 pi r0^2 P: nested loops with "
           "non-local memory",
           "total slip force per unit of pi r0^2 P", 0.10, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_all(d, [&](MuscleSpec& m) {
               m.hysteresis = {HysteresisKind::maxwell_slip, 1.5 * level, 0.10 * level, 0.002};
             });
             p["constant_n"] = 1.5 * level;
             p["pressure_fraction"] = 0.10 * level;
             p["median_slip_length_m"] = 0.002;
           });
}

void add_wrap_geometry_forms(std::vector<EffectDefinition>& defs) {
  add_form(defs, "elliptical_section", "wrap_geometry",
           "the wrapping surface is an ellipse, longer along the forearm (x 1.3 r_w) and flatter towards the muscle "
           "(x 0.75 r_w)",
           "semi-axis ratio a/b", 1.3 / 0.75, [](DeviceSpec& d, double level, nlohmann::json& p) {
             double ratio = 1.0;
             for_mounted(d, [&](MuscleSpec& m) {
               const double r = m.wrap.semi_x_m;
               m.wrap.semi_x_m = r * (1.0 + 0.3 * level);
               m.wrap.semi_y_m = r * (1.0 - 0.25 * level);
               ratio = m.wrap.semi_x_m / m.wrap.semi_y_m;
             });
             p["semi_axis_ratio"] = ratio;
             p["semi_x_gain"] = 1.0 + 0.3 * level;
             p["semi_y_gain"] = 1.0 - 0.25 * level;
           });
  add_form(defs, "offset_centre", "wrap_geometry",
           "the wrapping circle's centre sits 8 mm proximal and 8 mm towards the muscle from the hand's centre of "
           "rotation",
           "centre offset [m]", 0.008 * std::sqrt(2.0), [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_mounted(d, [&](MuscleSpec& m) {
               m.wrap.centre_x_m = -0.008 * level;
               m.wrap.centre_y_m = 0.008 * level;
             });
             p["centre_offset_m"] = {-0.008 * level, 0.008 * level};
           });
}

void add_passive_wrist_forms(std::vector<EffectDefinition>& defs) {
  add_form(defs, "exponential_limits", "passive_wrist",
           "the relaxed wrist stiffens exponentially towards its biological limits (Riener & Edrich 1999 form, "
           "e-folding 8 deg, limits of Table RoM)",
           "torque at each biological limit [N m]", 3.0, [](DeviceSpec& d, double level, nlohmann::json& p) {
             d.passive.limit_torque_nm = 3.0 * level;
             p["limit_torque_nm"] = 3.0 * level;
             p["e_folding_deg"] = to_deg(d.passive.limit_scale_rad);
           });
  add_form(defs, "direction_dependent", "passive_wrist",
           "stiffness differs per axis and direction: flexion x0.5, extension x2.2, ulnar x1.8, radial x3.5",
           "radial-deviation stiffness gain", 3.5, [](DeviceSpec& d, double level, nlohmann::json& p) {
             d.passive.direction_gain = {1.0 - 0.5 * level, 1.0 + 1.2 * level, 1.0 + 0.8 * level, 1.0 + 2.5 * level};
             p["direction_gain_flexion_extension_ulnar_radial"] = d.passive.direction_gain;
           });
}

void add_imu_bias_forms(std::vector<EffectDefinition>& defs) {
  add_form(defs, "forearm_imu_roll", "imu_bias",
           "the forearm IMU is rolled about the forearm's axis: FE reads cos(g) smaller and leaks into UR",
           "roll misalignment [rad]", to_rad(20.0), [](DeviceSpec& d, double level, nlohmann::json& p) {
             d.imu.roll_misalignment_rad = to_rad(20.0) * level;
             p["roll_misalignment_rad"] = d.imu.roll_misalignment_rad;
           });
  add_form(defs, "latency_jitter", "imu_bias",
           "the fused angles arrive late, with sample-to-sample jitter (+-100 ms at level 1; serial buffering)",
           "mean latency [s]", 0.3, [](DeviceSpec& d, double level, nlohmann::json& p) {
             d.imu.latency_s = 0.3 * level;
             d.imu.latency_jitter_s = 0.1 * level;
             p["latency_s"] = d.imu.latency_s;
             p["jitter_half_width_s"] = d.imu.latency_jitter_s;
           });
}

// The forms outside the classes a diagnosis names (label outside:<form>).
void add_outside_forms(std::vector<EffectDefinition>& defs) {
  add_form(defs, "fabric_creep", "outside:fabric_creep",
           "the fabric creeps over the day's session: L0 (1 + c ln(1 + I/60 s)), I the accumulated P/137 kPa time",
           "creep coefficient c", 0.012, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_all(d, [&](MuscleSpec& m) { m.creep_coefficient = 0.012 * level; });
             p["creep_coefficient"] = 0.012 * level;
             p["creep_reference_s"] = 60.0;
           });
  add_form(defs, "regulator_gain_drift", "outside:regulator_gain_drift",
           "the regulators' transducers read high as they warm up (30 min): the true pressure falls below the "
           "command while the monitors agree with it",
           "transducer gain error when warm", 0.10, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for (auto& r : d.regulators) r.gain_drift = 0.10 * level;
             p["gain_error_when_warm"] = 0.10 * level;
             p["warm_up_tau_s"] = 1800.0;
           });
  add_form(defs, "strap_slip", "outside:strap_slip",
           "the elbow band slips distally when the tension beats its 30 N grip, irreversibly until re-donned",
           "slip per newton above the grip [m/N]", 1.0 / 8000.0, [](DeviceSpec& d, double level, nlohmann::json& p) {
             for_mounted(d, [&](MuscleSpec& m) {
               m.slip_scale = level;
               m.slip_stiffness_n_per_m = 8000.0;
             });
             p["slip_m_per_n"] = level / 8000.0;
             p["grip_n"] = 30.0;
           });
  add_form(defs, "leaking_fitting", "outside:leaking_fitting",
           "the flexor's push-to-connect fitting leaks: P_m + a sqrt(P_m) = P_line, unseen by the monitor",
           "a [sqrt(kPa)]", 0.89, [](DeviceSpec& d, double level, nlohmann::json& p) {
             d.regulators[kFlexor].leak_coefficient_sqrt_kpa = 0.89 * level;
             p["leak_coefficient_sqrt_kpa"] = 0.89 * level;
             p["channel"] = "flexor";
           });
}

std::vector<EffectDefinition> build() {
  std::vector<EffectDefinition> defs;
  add_form(defs, "none", "none", "the nominal device (device-to-device variation only)", "", 0.0,
           [](DeviceSpec&, double, nlohmann::json&) {});
  add_mount_stretch_forms(defs);
  add_fpam_params_forms(defs);
  add_regulator_lag_forms(defs);
  add_hysteresis_forms(defs);
  add_wrap_geometry_forms(defs);
  add_passive_wrist_forms(defs);
  add_imu_bias_forms(defs);
  add_outside_forms(defs);
  return defs;
}

}  // namespace

const std::vector<EffectDefinition>& effect_definitions() {
  static const std::vector<EffectDefinition> defs = build();
  return defs;
}

const EffectDefinition* find_effect(const std::string& form) {
  for (const auto& d : effect_definitions())
    if (d.info.name == form) return &d;
  return nullptr;
}

void validate_effects(const std::vector<EffectSpec>& effects) {
  std::set<std::string> seen;
  for (const auto& e : effects) {
    if (find_effect(e.form) == nullptr) throw std::invalid_argument(fmt::format("unknown effect form '{}'", e.form));
    if (!(e.level > 0.0 && e.level <= 1.0))
      throw std::invalid_argument(fmt::format("effect form '{}': level {} is outside (0, 1]", e.form, e.level));
    if (!seen.insert(e.form).second)
      throw std::invalid_argument(fmt::format("effect form '{}' is given twice", e.form));
  }
}

const std::vector<FormInfo>& effect_forms() {
  static const std::vector<FormInfo> forms = [] {
    std::vector<FormInfo> out;
    for (const auto& d : effect_definitions()) out.push_back(d.info);
    return out;
  }();
  return forms;
}

}  // namespace softwrist::independent
