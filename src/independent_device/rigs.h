#pragma once
// The paper's rigs run on the simulated device, as one session of a lab day (the order matters for slow effects:
// tensile test, torque sweep, range of motion, tracking trials).
//  * tensile: the flexor fPAM in a tensile tester, 3 load/unload cycles at each of the paper's five pressures,
//    from its contracted state to full stretch (paper Sec. "Measurement of the fPAM force").
//  * torque sweep: the torque rig's flexor (Table torque_measurement_parameters), 8 plate angles x 5 pressures;
//    repetitions alternate ascending angles with ascending pressures and descending angles with descending
//    pressures, so loading history differs between them; each point is read after a 4 s hold.
//  * range of motion: the prototype's relaxed wrist, each muscle inflated alone from rest for 4 s, the IMU angle
//    (zeroed at the trial's start) read at the end.
//  * tracking: the paper's controller closed on the simulated IMUs: planar FE steps with the hand supported on a
//    table, the 2-DoF near-ellipse in gravity. Each trial starts from the hand placed near rest while the initial
//    13.8 kPa are still filling (not at rest), and zeroes the IMU angles at t = 0.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "independent_device/device.h"
#include "independent_device/table.h"

namespace softwrist::independent {

struct Session {
  Session(const DeviceSpec& spec, std::uint64_t session_seed, bool with_noise);

  DeviceSpec device;
  std::uint64_t seed;
  bool noisy;               // false: the noise-free reference (no sensor noise, no quantisation, no human scatter)
  MuscleState flexor_fpam;  // the tensile specimen and the rig's flexor are one fPAM
  std::array<MuscleState, 4> prototype;
  std::vector<Regulator> regulators;
  double clock_s = 0.0;  // time since the session (and the regulators' warm-up) began
};

inline constexpr std::array<double, 5> kPaperPressuresKpa{0.0, 34.0, 68.0, 103.0, 137.0};

Table run_tensile(Session& session);
// torque_includes: "muscle" | "muscle+passive_wrist" | "muscle+passive_wrist+hand_weight" | "baseline_subtracted".
Table run_torque_sweep(Session& session, const std::string& torque_includes, Posture posture, int repetitions);
Table run_rom(Session& session, Posture posture, int repetitions);

enum class TrackingTask { planar_steps, ellipse };
Table run_tracking(Session& session, TrackingTask task, Posture posture, int trials, double length_s);

// The torque rig's flexor torque at a wrist angle and muscle pressure for a device and muscle state.
MuscleForce torque_rig_flexor(const DeviceSpec& device, const MuscleState& state, double angle_rad,
                              double pressure_kpa);

}  // namespace softwrist::independent
