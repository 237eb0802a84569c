#include "independent_device/device.h"

#include "independent_device/units.h"

namespace softwrist::independent {
namespace {

MuscleSpec make_muscle(double d1_cm, double w1_cm, double d2_cm, double w2_cm, double l0_cm, double rw_cm) {
  MuscleSpec m;
  m.placement = {d1_cm / 100.0, w1_cm / 100.0, d2_cm / 100.0, w2_cm / 100.0};
  m.rest_length_m = l0_cm / 100.0;
  m.wrap = {rw_cm / 100.0, rw_cm / 100.0, 0.0, 0.0};
  return m;
}

}  // namespace

DeviceSpec nominal_device() {
  DeviceSpec d;
  // Tensile specimen: measured L0 = 34.0 cm (Table tensile_testing_parameters); gripped, so no wrap and no mounts.
  d.tensile_specimen = make_muscle(0, 0, 0, 0, 34.0, 0.0);
  // Torque rig: Table torque_measurement_parameters (d1 19.47, w1 4.93, d2 8.30, w2 3.38, L0 32.00, r_w 3.99 cm).
  d.rig_flexor = make_muscle(19.47, 4.93, 8.30, 3.38, 32.00, 3.99);
  // Prototype: Table RoM placements and measured L0. The paper gives no wrist radius for the prototype: FE uses the
  // torque rig's fitted 3.99 cm (same wrist); UR uses 3.0 cm, half the wrist breadth (~6 cm for adults, e.g.
  // Greiner 1991, US Army hand anthropometry), as the deviation muscles wrap the radial/ulnar borders.
  d.prototype[kFlexor] = make_muscle(20.5, 5.7, 4.0, 4.0, 29.0, 3.99);
  d.prototype[kExtensor] = make_muscle(24.5, 3.7, 5.4, 4.1, 32.0, 3.99);
  d.prototype[kUlnar] = make_muscle(21.1, 7.1, 1.0, 3.4, 28.5, 3.0);
  d.prototype[kRadial] = make_muscle(21.3, 4.8, 2.3, 6.0, 27.0, 3.0);
  // The paper models every muscle with the flexor's fPAM law and the rig's stretching coefficients; so do we.
  return d;
}

nlohmann::json apply_variation(DeviceSpec& device, Rng& rng) {
  // Tolerances below a lab's resolution (so `none` is "nominal" to anyone measuring): r0 1.5 % (the paper's own
  // fitted r0 scatters 3 % between pressures), e_max 0.004 (its fit scatters 0.01), anchors 1.5 mm and L0 1 mm
  // (motion-capture marker placement), stretching coefficients 8 % (the paper averages K over points that scatter
  // far more), wrist radius 2 %, relaxed-wrist stiffness 6 % and damping 10 % (day-to-day scatter of passive wrist
  // stiffness is 10-20 %, Formica 2012), hand mass 4 %, regulator time constant 10 %, monitor offset 0.15 kPa and
  // gain 0.5 % (QB3 +-0.5 % FS), hand-on-plate angle 1 deg.
  nlohmann::json drawn = nlohmann::json::object();
  auto vary_law = [&](FpamLaw& law, const std::string& name) {
    law.radius_scale = rng.normal(1.0, 0.015);
    law.max_contraction_offset = rng.normal(0.0, 0.004);
    drawn[name + ".radius_scale"] = law.radius_scale;
    drawn[name + ".max_contraction_offset"] = law.max_contraction_offset;
  };
  auto vary_mounted = [&](MuscleSpec& m, const std::string& name) {
    m.placement.d1_m += rng.normal(0.0, 0.0015);
    m.placement.w1_m += rng.normal(0.0, 0.0015);
    m.placement.d2_m += rng.normal(0.0, 0.0015);
    m.placement.w2_m += rng.normal(0.0, 0.0015);
    m.rest_length_m += rng.normal(0.0, 0.001);
    m.mount.k_forearm_n_per_m2 *= rng.normal(1.0, 0.08);
    m.mount.k_hand_n_per_m2 *= rng.normal(1.0, 0.08);
    const double rw = rng.normal(1.0, 0.02);
    m.wrap.semi_x_m *= rw;
    m.wrap.semi_y_m *= rw;
    drawn[name + ".placement_m"] = {m.placement.d1_m, m.placement.w1_m, m.placement.d2_m, m.placement.w2_m};
    drawn[name + ".rest_length_m"] = m.rest_length_m;
    drawn[name + ".k_n_per_m2"] = {m.mount.k_forearm_n_per_m2, m.mount.k_hand_n_per_m2};
    drawn[name + ".wrap_radius_m"] = m.wrap.semi_x_m;
  };
  // The tensile specimen and the rig's flexor are one fPAM: one law.
  vary_law(device.rig_flexor.law, "rig_flexor");
  device.tensile_specimen.law = device.rig_flexor.law;
  device.tensile_specimen.rest_length_m += rng.normal(0.0, 0.001);
  vary_mounted(device.rig_flexor, "rig_flexor");
  for (std::size_t i = 0; i < 4; ++i) {
    const std::string name = std::string("prototype.") + kMuscleNames[i];
    vary_law(device.prototype[i].law, name);
    vary_mounted(device.prototype[i], name);
  }
  for (std::size_t i = 0; i < 4; ++i) {
    RegulatorSpec& r = device.regulators[i];
    r.tau_s *= rng.normal(1.0, 0.10);
    r.monitor_offset_kpa = rng.normal(0.0, 0.15);
    r.monitor_gain = rng.normal(1.0, 0.005);
    drawn[std::string("regulator.") + kMuscleNames[i]] = {r.tau_s, r.monitor_gain, r.monitor_offset_kpa};
  }
  PassiveWrist& w = device.passive;
  w.stiffness_fe_nm_per_rad *= rng.normal(1.0, 0.06);
  w.stiffness_ur_nm_per_rad *= rng.normal(1.0, 0.06);
  w.damping_fe_nms_per_rad *= rng.normal(1.0, 0.10);
  w.damping_ur_nms_per_rad *= rng.normal(1.0, 0.10);
  drawn["wrist.stiffness_nm_per_rad"] = {w.stiffness_fe_nm_per_rad, w.stiffness_ur_nm_per_rad};
  drawn["wrist.damping_nms_per_rad"] = {w.damping_fe_nms_per_rad, w.damping_ur_nms_per_rad};
  device.hand.mass_kg *= rng.normal(1.0, 0.04);
  drawn["hand.mass_kg"] = device.hand.mass_kg;
  device.rig_angle_offset_rad = to_rad(rng.normal(0.0, 1.0));
  drawn["rig.hand_angle_offset_deg"] = to_deg(device.rig_angle_offset_rad);
  return drawn;
}

}  // namespace softwrist::independent
