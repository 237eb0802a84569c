#pragma once
// Replaying real trials with a model: the same held angles and pressures (torque sweeps), the same muscle and
// pressure (range of motion), the same contraction and pressure (tensile tests), the same commands from the same
// start (trajectories), and the residual of each measurement.
//
// How each kind is replayed, and why:
//  - torque sweeps and tensile tests are static: the analytic model (physics::muscle_state, physics::fpam_force) is
//    the law the plugin evaluates, and the MuJoCo simulation is cross-checked against it in tests/sim; replaying
//    them analytically costs microseconds instead of a simulated hold of a second per point.
//  - range of motion: the MuJoCo model, each muscle alone from the neutral wrist, settled for 6 s (as the
//    range-of-motion experiment). The analytic statics (sim::settled_angle) leave out the 3D tendon paths and
//    differ from the simulation by up to a degree, more than the motion capture's noise. Rows are taken in the order
//    measured: a variant whose previous condition's muscle had not vented when the angles were zeroed
//    (ModelVariant::rom_residual_fraction) reads each limit from that pose (predict_rom).
//  - trajectories are dynamic: the MuJoCo model with the fPAM plugin, generated from the variant's device, from the
//    neutral wrist at rest; the IMU pair is sampled every 10 ms, late by the variant's latency and offset by its
//    bias. Where the log has the regulators' measured pressures, the muscles are driven by them (PressureSource) and
//    the regulators alone replay the logged commands (delayed by the dead time), compared with the measured
//    pressures; otherwise the commands drive the simulated regulators and the muscles open loop.
//
// Prepared once per data set: each measurement's repeat group (same condition), its split unit (the training /
// held-out split and the bootstrap resample whole units), where it lies (angle, pressure, muscle, motion), and each
// trial's repeat-to-repeat noise.

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "diagnosis/effects.h"
#include "diagnosis/real_data.h"
#include "physics/pressure_regulator.h"
#include "sim/model.h"
#include "sim/plugins.h"

namespace softwrist::diagnosis {

struct Point {
  double measured = 0.0;  // in the trial's unit: N m (sweeps), deg (range of motion, trajectories), N (tensile)
  int group = 0;          // repeat group within the trial: the same condition measured again, or a 1 s block
  int unit = 0;           // split and bootstrap unit within the trial
  bool heldout = false;
  // Where it lies, for the localisation (NaN or -1 where it does not apply).
  double angle_deg = NAN;  // wrist angle (own direction for range of motion)
  double pressure_kpa = NAN;
  double contraction = NAN;
  int muscle = -1;
  int channel = -1;  // trajectories: 0 flexion/extension, 1 ulnar/radial; 2 + muscle: its measured pressure
  int motion = 0;    // +1 moving towards flexion/ulnar (loading on the tensile rig), -1 the other way
  double t_s = NAN;
  int repetition = -1;  // the same condition measured again later (tensile cycle, sweep or range-of-motion repetition)
  // A torque sweep's condition regardless of the side its held angle was reached from (-1 elsewhere): where no
  // condition repeats from one side, its repetitions from either side bound the noise (estimate_noise).
  int condition = -1;
  // A torque sweep's setting (-1 elsewhere): a run of consecutive readings at one held angle of one repetition, which
  // share the hand's seat and the relaxed wrist's tone (setting_scatter.h).
  int setting = -1;
};

struct PreparedTrial {
  const Trial* trial = nullptr;
  std::string name;  // the trial's name; "<name> pressures" for a trajectory's measured pressures
  // A trajectory with measured pressures is prepared twice: its angles, and (with this set) its pressures, each with
  // its own unit and noise. The pressures tell a regulator's lag from an IMU's latency, which delay the angles alike.
  bool pressures = false;
  // A trajectory's angles replayed from its measured pressures (PressureSource::kMeasuredWhereLogged): the
  // regulators' response does not reach them. The readings that drive them, one per row (ReplayEngine::
  // drive_readings).
  bool angles_from_measured_pressures = false;
  std::vector<control::Pressures> drive_readings;
  std::vector<Point> points;
  std::string unit;    // of measured and residuals
  double noise = 0.0;  // repeat-to-repeat standard deviation of one measurement, in `unit`
  int noise_dof = 0;   // its degrees of freedom
  // The variance of a repeat group's mean residual is noise^2 * group_inflation / n: 1 for white noise, more for a
  // noise that wanders (trajectories with repetitions, repeat_noise.h).
  double group_inflation = 1.0;
  std::string noise_source;  // how it was estimated
  // Torque sweeps: the standard deviation of the offset a setting's readings share, in `unit` (setting_scatter.h);
  // 0 where none was found.
  double setting_scatter = 0.0;
  double training_end_s = 0.0;  // trajectories: the training part ends here
  // Trajectories: the repeated task it is one repetition of (repeat_noise.h, an index into repeat_sets), -1 for none.
  int repeat_set = -1;
};

// Whether `effect` changes `trial`'s replay: a kind it acts on, and not the angles of a trajectory replayed from its
// measured pressures where the effect acts only through the regulators, nor a range of motion whose angles were not
// zeroed before each condition (the regulators reach a settled limit only through the zero); a trajectory's measured
// pressures only where it acts through the regulators; a torque sweep for the relaxed wrist only where the reading
// includes the wrist. The trials it acts on are those an effect is scored on (explained_in_acted_on).
bool acts_on(const EffectSpec& effect, const PreparedTrial& trial);

// Measured minus predicted, for each point of `trial`.
std::vector<double> residuals_of(const PreparedTrial& trial, const std::vector<double>& predicted);

// Groups, units, the split and the noise of each trial (the noise of sweeps from the nominal model's residuals, so
// that the held angle's jitter within a group does not count as noise).
class ReplayEngine;
std::vector<PreparedTrial> prepare(const RealData& data, ReplayEngine& engine, const ModelVariant& nominal);

// The simulation steps of the replays, measured against replays at 0.5 ms of the paper-sized data set (72 s
// trajectory, commands every 14 ms; 24 range-of-motion conditions; the replays dumped by a throwaway change to this
// file, not kept):
//  - trajectories: the generated model's 1 ms. At 2 ms their angles differ from the 0.5 ms replay by 0.033 / 0.058
//    deg RMS (flexion / ulnar), at 1 ms by 0.028 / 0.056: the step adds little to what the first-order integrator
//    leaves at 1 ms. On the paper's device (`synthesize`, 72 s) the nominal's predictions at 2 ms differ from those at
//    1 ms by 0.0064 deg RMS (2.6 % of the angles' noise) and 0.0087 kPa (3 % of the pressures'), and would make
//    `bench diagnose` 1.6 times as fast. But data made by the catalogue's own simulated device (at 1 ms) are then not
//    reproduced by the nominal, and fits of weakly determined parameters move along their valleys: under BOBYQA the
//    fPAM's four (r0 x 0.919 for the true 0.9; Levenberg-Marquardt now reaches the floor at either step, r0 x 0.9003
//    and 0.9005), and the tolerance fit's ulnar hand anchor, 2 mm nearer the wrist, came out at its box's edge (d2
//    0.7 cm for the true 0.8; DiagnosisTest.OneMusclesAnchorWithinItsToleranceIsNone): kept at 1 ms.
//  - range of motion: 2 ms. A settled angle is an equilibrium, which does not depend on the step: within 0.0019 deg
//    of the 1 ms replay's. (At 4 ms, within 0.0011 deg, the same fit of four parameters came out at r0 x 0.921: it
//    lies in a flat valley that such differences move it along.)
//  - coarse (Fidelity::kCoarse): 5 ms, both kinds, for a fit's finite differences and the ranking of its start grid
//    only. The integrator's error varies smoothly with the parameters and cancels in a difference of two replays at
//    the same step, while every value a fit compares with another's, accepts or reports is a fine replay's. 5 ms puts
//    the IMU's 10 ms samples on steps, and the wrist's fastest mode (about 15 Hz on the paper's device) and the
//    limits' stiffening (sqrt((A/s)/I) dt = 0.35, wrist_sim.cc) stay within the Euler step's stable reach. On `bench
//    diagnose` the tolerance fit then ends at a training error of 43.493 against 43.492 with fine differences (4 ms:
//    43.64, 2 ms: 43.53; its valley is flat), a coarse replay costs 29 ms against 130 ms.
struct ReplaySteps {
  double trajectory = 0.001;  // [s]
  double settle = 0.002;      // [s]
  double coarse = 0.005;      // [s]
};

// Which step a replay takes (ReplaySteps): kCoarse only for a Jacobian's differences, never for a value compared
// with a fine one.
enum class Fidelity { kFine, kCoarse };

// What drives the muscles in a trajectory's replay.
//  - kMeasuredWhereLogged (default): where the log has the regulators' measured pressures (the bridge logs them), the
//    muscles are driven by those (smoothed, drive_readings; through the variant's monitor calibration, linear
//    between rows), and the logged
//    commands drive the regulators alone, whose pressures are compared with the measured ones. A model error of the
//    regulator then stays in the pressures, where it is measured, instead of travelling on into the angles, where it
//    looked like a muscle's or the wrist's error: a measured signal between two parts of a chain lets each part be
//    judged on its own input and output (a cascade identified piecewise, as system identification does where an
//    intermediate signal is measured; Ljung, System Identification, 2nd ed., 1999). The measured pressures' noise
//    reaches the angles only through the wrist's low-pass response.
//  - kCommands: the commands through the simulated regulators into the muscles (the only choice without measured
//    pressures), as before this option existed.
enum class PressureSource { kMeasuredWhereLogged, kCommands };

// What the simulated replays cost (cached ones not counted): where a diagnosis's time goes.
struct ReplayStats {
  long trajectories = 0;
  double trajectory_s = 0.0;      // [s] their wall time, summed over threads
  double trajectory_sim_s = 0.0;  // [s] of the trials' time simulated
  long settles = 0;               // range-of-motion replays (each muscle and pressure of a trial)
  double settle_s = 0.0;          // [s] their wall time, summed over threads
  long cache_hits = 0;
};

// Runs replays; holds the MuJoCo plugins and a small cache of simulated trajectories (a fit of the IMU's offset and
// latency changes only what is read from a simulation, so it reuses one). Thread-safe.
class ReplayEngine {
 public:
  explicit ReplayEngine(sim::PluginSet plugins, ReplaySteps steps = {},
                        PressureSource pressure_source = PressureSource::kMeasuredWhereLogged)
      : plugins_(std::move(plugins)), steps_(steps), pressure_source_(pressure_source) {}
  // The model's value for each point of `trial` (same order); with `training_only`, held-out points of trajectories
  // are left NaN and the simulation stops at the end of the training part.
  std::vector<double> predict(const PreparedTrial& trial, const ModelVariant& variant, bool training_only,
                              Fidelity fidelity = Fidelity::kFine);
  // Throws std::runtime_error naming why the model cannot replay the trial (a pressure beyond its regulators).
  void check_replayable(const Trial& trial, const ModelVariant& variant) const;
  ReplayStats stats() const;
  // Whether this engine replays `trial`'s angles from its measured pressures.
  bool angles_from_measured_pressures(const Trial& trial) const;
  // Whether `trial`'s replay depends on the simulation's step (Fidelity): a range of motion and a trajectory's angles
  // or pressures simulated in MuJoCo; not sweeps and tensile tests (analytic), nor measured pressures compared with
  // the regulators replayed alone (always at the fine step).
  bool depends_on_step(const PreparedTrial& trial) const;
  // The measured pressures' readings [kPa] that drive `trial`'s angles, one per row: `nominal`'s regulators'
  // readings replaying the commands, plus the measured readings' difference from them smoothed over
  // kDriveSmoothing. Raw readings carry the sensor's white noise into the muscles, and through the wrist's
  // resonance into the angles (0.31 kPa of it gave 0.29 deg RMS on the paper's device, more than the IMU's noise);
  // the smoothed difference keeps what the regulators do that the nominal's do not (a lag, a slow vent, an
  // overshoot: slower than the smoothing), and the nominal's regulators give the fast part of a command's step.
  std::vector<control::Pressures> drive_readings(const Trial& trial, const ModelVariant& nominal) const;

  // A range-of-motion pose: the muscles' pressures, and the muscle in whose own direction its angle is read.
  struct RomPose {
    std::array<double, 4> pressure_kpa{};
    int read = 0;
    auto operator<=>(const RomPose&) const = default;
  };

 private:
  struct Simulated {
    double dt = 0.0;
    std::vector<double> fe, ur;  // [rad] true joint angles every dt from t = 0 (range of motion: settled angles)
    std::array<std::vector<double>, 4> pressure_kpa;  // the regulated pressures every dt (trajectories)
  };
  // The cached result under `key`, or compute() cached (at most 32 entries).
  std::shared_ptr<const Simulated> cached(const std::string& key,
                                          const std::function<std::shared_ptr<const Simulated>()>& compute);
  sim::Model load_model(const sim::DeviceDescription& device, const Trial& trial, double timestep) const;
  std::vector<double> predict_sweep(const Trial& trial, const sim::DeviceDescription& device) const;
  static std::vector<double> predict_tensile(const Trial& trial, const sim::DeviceDescription& device);
  std::vector<double> predict_rom(const Trial& trial, const ModelVariant& variant, Fidelity fidelity);
  std::vector<double> predict_trajectory(const PreparedTrial& prepared, const ModelVariant& variant, bool training_only,
                                         Fidelity fidelity);
  // A trajectory's logged commands, or its measured pressures, replayed up to `horizon` [s] at `timestep` [s].
  // `drive`: the readings that drive the muscles (drive_readings), or null for the commands.
  std::shared_ptr<const Simulated> simulate(const Trial& trial, const ModelVariant& variant, double horizon,
                                            const std::vector<control::Pressures>* drive, double timestep);
  using RegulatorStates = std::array<physics::RegulatedPressure, 4>;
  // The regulators' state at a trajectory's first row as the model has it: settled under the first command where the
  // angles were zeroed (as the wrist is pre-settled), vented otherwise.
  RegulatorStates regulator_start(const Trial& trial, const ModelVariant& variant) const;
  // The regulators alone replaying the logged commands from `start` up to `horizon` [s], step by step as the plugin
  // integrates them in MuJoCo (pressure_kpa only). At the step of the first row (the last at or before its time) the
  // state is stored in `model_at_first_row` where given, then replaced by `at_first_row` where given.
  Simulated replay_regulators(const Trial& trial, const ModelVariant& variant, double horizon,
                              const RegulatorStates& start, const RegulatorStates* at_first_row = nullptr,
                              RegulatorStates* model_at_first_row = nullptr) const;
  // The regulators' state at the first row that fits the first measured pressures of a trajectory's `prepared`
  // pressures (replay.cc says why).
  RegulatorStates measured_regulator_start(const PreparedTrial& prepared, const ModelVariant& variant) const;
  // The settled angle [deg, own direction of each pose's `read` muscle] of each pose, in `fe`.
  std::shared_ptr<const Simulated> settle(const Trial& trial, const sim::DeviceDescription& device,
                                          const std::vector<RomPose>& poses, double timestep);
  sim::PluginSet plugins_;
  ReplaySteps steps_;
  PressureSource pressure_source_;
  mutable std::mutex mutex_;  // guards cache_ and stats_
  ReplayStats stats_;
  std::map<std::string, std::shared_ptr<const Simulated>> cache_;
};

}  // namespace softwrist::diagnosis
