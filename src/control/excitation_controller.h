#pragma once
// The calibration routine's "controller": it plays a fixed schedule of pressures and ignores the IMUs (open loop), so
// that what the sensors record is the device's own answer to a known excitation (softwrist calibrate,
// docs/calibration.md). The schedule is a list of segments, each a linear ramp between two sets of pressures; a step
// is a segment that starts where it ends.
//
// The default routine (excitation_routine) is designed around what the exosuit's own sensors (two IMUs, four pressure
// monitors; no torque sensor) can tell apart:
//  - each muscle alone at three pressures, held: the angle where it settles against the relaxed wrist, at forces
//    from low to high. The mounts stretch with the square root of the force (Eqn. fabric_stretching), the relaxed
//    wrist and the fPAM scale with angle and pressure, so the three levels separate the mount stiffness from the
//    wrist stiffness;
//  - the steps' edges, in the measured pressures: the regulators' time constant and dead time;
//  - each muscle on a slow ramp up and down: the same angles reached loading and unloading (the fabric's hysteresis);
//  - both muscles of a pair at once (co-contraction): the pair's stiffness about neutral without a net torque.

#include <string>
#include <vector>

#include "control/controller.h"

namespace softwrist::control {

struct ExcitationSegment {
  double duration_s = 0.0;
  Pressures from_kpa{}, to_kpa{};  // flexor, extensor, ulnar, radial
  std::string part;                // which part of the routine: "flexor steps", "ulnar/radial co-contraction", ...
};

struct ExcitationRoutineParameters {
  std::vector<double> step_levels_kpa = {45.0, 90.0, 137.0};  // each muscle alone, held at each in turn
  double hold_s = 2.5;                                        // every held level, and each vented pause
  double ramp_s = 5.0;                                        // 0 -> the top level, and back
  double co_contraction_kpa = 70.0;                           // both muscles of a pair, then both at the top level
  double start_rest_s = 1.0;                                  // vented before the first step
  // A step's edge is a ramp this steep: the device slews commands at its own rate limit (1370 kPa/s by default,
  // docs/bridge-protocol.md), so a sharper edge would be logged as a command the regulators never received.
  double edge_rate_kpa_s = 1000.0;
};

// The default routine: every muscle in turn (steps, a vented pause, a ramp up and down, a pause), then each pair
// co-contracted; every change of level an edge at edge_rate_kpa_s followed by the hold. Throws std::invalid_argument
// for a level outside [0, max_kpa] or a non-positive duration or rate.
std::vector<ExcitationSegment> excitation_routine(const ExcitationRoutineParameters& parameters, double max_kpa);

// The routine's length [s].
double routine_duration_s(const std::vector<ExcitationSegment>& segments);

// The steepest commanded change [kPa/s] of any muscle (the edges).
double routine_max_ramp_kpa_s(const std::vector<ExcitationSegment>& segments);

class ExcitationController final : public Controller {
 public:
  // Throws std::invalid_argument for an empty schedule, a segment of zero or negative length, or a pressure outside
  // [0, max_kpa] (the routine never asks the regulators for more than their range).
  ExcitationController(std::vector<ExcitationSegment> segments, double max_kpa, double period_s = 0.014);

  std::string name() const override { return "excitation"; }
  double period_s() const override { return period_s_; }
  void reset() override {}
  // The scheduled pressures at `t_s`; vented after the schedule's end.
  Pressures command(double t_s, const Reference& desired, const ImuReading& reading) override;

  const std::vector<ExcitationSegment>& segments() const { return segments_; }
  double duration_s() const { return duration_s_; }

 private:
  std::vector<ExcitationSegment> segments_;
  double period_s_;
  double duration_s_;
};

}  // namespace softwrist::control
