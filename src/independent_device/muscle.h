#pragma once
// One fPAM as mounted: force law + path over the wrist + compliant mounts + internal friction + slow states.
// The tension F is found self-consistently: the mounts' take-up at F shortens the muscle, which lowers its force,
// so F solves F = F_muscle(e(F)). (The paper evaluates the stretch at the force of the unstretched placement; a
// series spring is in equilibrium only at the fixed point, so that is what a real device does.) The residual is
// strictly decreasing in F, so the root is unique and bracketed by [0, F_muscle(e(0))].

#include "independent_device/fpam.h"
#include "independent_device/geometry.h"
#include "independent_device/hysteresis.h"
#include "independent_device/mount.h"

namespace softwrist::independent {

struct MuscleSpec {
  Placement placement;
  WrapSurface wrap;
  double rest_length_m = 0.32;  // L0, the fully stretched length
  FpamLaw law;
  MountLaw mount;
  HysteresisLaw hysteresis;
  // outside:fabric_creep -- L0 grows with the pressure-time the fabric has carried, logarithmically as nylon
  // creeps (Findley's power/log law; e.g. Findley, Lai & Onaran 1976): L0 (1 + c ln(1 + I / I_ref)),
  // I = integral of P / 137 kPa dt.
  double creep_coefficient = 0.0;
  double creep_reference_s = 60.0;
  // outside:strap_slip -- the elbow band slides on the skin when the tension beats its grip; the slip is
  // irreversible until the band is put on again: slip = scale * max over history of (F - F_grip) / k_catch.
  double slip_scale = 0.0;
  double slip_threshold_n = 30.0;
  double slip_stiffness_n_per_m = 2500.0;
};

struct MuscleState {
  HysteresisState hysteresis;
  bool has_length = false;
  double muscle_length_m = 0.0;  // last fabric length (drives the friction state)
  double pressure_time_s = 0.0;  // creep integral I
  double strap_slip_m = 0.0;
};

struct MuscleForce {
  double force_n = 0.0;
  double torque_nm = 0.0;  // on the hand, positive in the muscle's own direction
  double contraction = 0.0;
  double muscle_length_m = 0.0;
  bool wrapped = false;
};

double effective_rest_length_m(const MuscleSpec& spec, const MuscleState& state);
// Tension and torque at the muscle's own angle theta and muscle pressure; does not change the state.
// force_hint_n: the previous step's tension, if any (speeds the root search; the root is the same).
MuscleForce solve_muscle(const MuscleSpec& spec, const MuscleState& state, double theta_own_rad, double pressure_kpa,
                         double force_hint_n = -1.0);
// Tension when the fabric length is imposed (a tensile tester's grips; no mounts).
MuscleForce solve_muscle_at_length(const MuscleSpec& spec, const MuscleState& state, double muscle_length_m,
                                   double pressure_kpa);
// Commits a solution: friction follows the length change, creep accrues, the strap slips.
void advance_muscle(const MuscleSpec& spec, MuscleState& state, const MuscleForce& solved, double pressure_kpa,
                    double dt_s);

}  // namespace softwrist::independent
