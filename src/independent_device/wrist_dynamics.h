#pragma once
// The relaxed human wrist carrying the hand: a 2-DoF universal joint (flexion-extension about an axis fixed in the
// forearm, then ulnar-radial deviation about an axis in the proximal carpal row), passive tissue torques, gravity.
//
// Hand (with the glove, IMU and the fPAMs' distal ends): mass fraction 0.006 of body mass, centre of mass at 0.506
// and radius of gyration about the wrist 0.587 of the wrist-to-knuckle-II length (Dempster via Winter,
// "Biomechanics and Motor Control of Human Movement", 4th ed., Table 4.1), 75 kg subject, 0.14 m segment, plus 50 g
// of glove and hardware (the paper: 160 g wearable in all). Inertia about the wrist ~0.0034 kg m^2, close to the
// identified 0.0025-0.0035 kg m^2 of Charles & Hogan (J Biomech 44:614, 2011).
// Relaxed wrist, nominal: linear stiffness 1.0 N m/rad about both axes and damping 0.03 N m s/rad (Charles & Hogan
// 2011; Formica et al., J Neurophysiol 108:3158, 2012, report FE ~1 N m/rad for relaxed subjects).
// passive_wrist forms: exponential stiffening towards the biological range of motion (double-exponential passive
// moment of Riener & Edrich, J Biomech 32:539, 1999, with the limits of the paper's Table RoM), and stiffness that
// differs per axis and direction (deviation stiffer than flexion-extension, radial stiffest, as in Formica 2012).
// Equations of motion (Lagrange, hand frame inertia diag(I_axial, I_perp, I_perp), angles fe = theta, ur = phi):
//   (I_a sin^2 phi + I_p cos^2 phi) theta'' = tau_fe - 2 sin phi cos phi (I_a - I_p) theta' phi'
//   I_p phi'' = tau_ur + sin phi cos phi (I_a - I_p) theta'^2
// integrated semi-implicitly (symplectic Euler) at 1 ms.

#include <array>

namespace softwrist::independent {

struct HandSegment {
  double mass_kg = 0.50;
  double com_m = 0.071;
  double inertia_perp_kg_m2 = 0.0034;    // about the FE and UR axes through the wrist
  double inertia_axial_kg_m2 = 0.00034;  // about the hand's long axis (flat plate 8.5 cm x 3 cm)
};

struct PassiveWrist {
  double stiffness_fe_nm_per_rad = 1.0, stiffness_ur_nm_per_rad = 1.0;
  double damping_fe_nms_per_rad = 0.03, damping_ur_nms_per_rad = 0.03;
  // passive_wrist: direction_dependent -- stiffness gains for flexion, extension, ulnar, radial.
  std::array<double, 4> direction_gain{1.0, 1.0, 1.0, 1.0};
  // passive_wrist: exponential_limits -- torque A at each biological limit, e-folding angle s.
  double limit_torque_nm = 0.0;
  double limit_scale_rad = 0.14;  // 8 deg
  // Biological range of motion (paper Table RoM): flexion, extension, ulnar, radial.
  std::array<double, 4> limit_rad{1.4120, 0.9774, 0.6824, 0.4049};
};

// The subject on the day and trial: where the relaxed wrist rests, how toned it is.
struct WristCondition {
  double rest_fe_rad = 0.0, rest_ur_rad = 0.0;
  double stiffness_scale = 1.0;
};

enum class Posture { hand_supported, gravity_fe, gravity_ur };

struct WristState {
  double fe = 0.0, ur = 0.0, fe_rate = 0.0, ur_rate = 0.0;
};

// Passive tissue torque {fe, ur} (positive: flexion, ulnar).
std::array<double, 2> passive_torque_nm(const PassiveWrist& wrist, const WristCondition& condition,
                                        const WristState& state);
// Gravity torque {fe, ur}: gravity_fe is the forearm horizontal and pronated (palm down: gravity flexes),
// gravity_ur the forearm horizontal in mid-pronation (thumb up: gravity deviates ulnarly).
std::array<double, 2> gravity_torque_nm(const HandSegment& hand, Posture posture, double fe, double ur);
// One step with the applied (muscle + passive + gravity) torques; ur_locked: the hand's edge rests on a table.
void step_wrist(WristState& state, const HandSegment& hand, const std::array<double, 2>& torque_nm, double dt_s,
                bool ur_locked);

}  // namespace softwrist::independent
