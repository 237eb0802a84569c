#pragma once
// The "real" data a gap diagnosis compares the model with: every trial log under a directory (docs/log-format.md),
// whether written by a hardware trial, an imported CSV (import.h) or a simulated experiment standing in for a device.
// Each log becomes one or more trials in SI units and the wrist's sign convention; a file that cannot be read is
// reported with its reason and the rest of the data is still used.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "control/plant.h"
#include "diagnosis/conventions.h"
#include "experiments/trial_log.h"
#include "sim/device.h"

namespace softwrist::diagnosis {

enum class TrialKind { kTorqueSweep, kRangeOfMotion, kTensile, kTrajectory };
const char* to_string(TrialKind kind);

// The torque of one muscle with the wrist held (Section Torque applied by the exosuit).
struct SweepPoint {
  sim::MuscleIndex muscle = sim::kFlexor;
  double angle = 0.0;     // [rad] the held wrist angle, flexion / ulnar positive
  double pressure = 0.0;  // [Pa]
  double torque = 0.0;    // [N m] positive in the muscle's own direction
  int repetition = 0;
  // How the wrist came to this held angle, from the log's order: +1 moving towards flexion / ulnar deviation, -1 the
  // other way, 0 not known (a repetition's first angle). A fabric muscle's force depends on it (hysteresis).
  int motion = 0;
};

// Where one muscle alone settles the relaxed wrist (Section Range of motion).
struct RomPoint {
  sim::MuscleIndex muscle = sim::kFlexor;
  double pressure = 0.0;  // [Pa]
  double limit = 0.0;     // [rad] in the muscle's own direction
  int repetition = 0;
};

// One reading of an fPAM tensile test (Fig. TensileTest).
struct TensilePoint {
  double pressure = 0.0;     // [Pa]
  double contraction = 0.0;  // contraction ratio eps
  double force = 0.0;        // [N]
  bool loading = true;       // stretching (loading) or relaxing (unloading); loading when the log does not say
  int cycle = 0;
};

// One control-loop instant of a trajectory: what was commanded and what the IMUs said.
struct TrajectorySample {
  double t = 0.0;                    // [s] from the start of the run
  control::Pressures command_kpa{};  // flexor, extensor, ulnar, radial
  double fe = 0.0, ur = 0.0;         // [rad] measured wrist angles
  // What the regulators' monitor outputs read (`p_<muscle>_kpa`: hardware logs, imports that have them).
  std::optional<control::Pressures> measured_kpa;
};

struct Trial {
  TrialKind kind = TrialKind::kTorqueSweep;
  std::string name;         // the log's path under the data directory, and the case for trajectories
  std::string file;         // the CSV, for messages
  Conventions conventions;  // how it was measured, as its log states (conventions.h)
  std::vector<SweepPoint> sweep;
  std::vector<RomPoint> rom;
  std::vector<TensilePoint> tensile;
  std::vector<TrajectorySample> trajectory;
  std::size_t size() const;
};

struct FileProblem {
  std::string file;
  std::string reason;
};

struct RealData {
  std::vector<Trial> trials;
  std::vector<FileProblem> problems;  // files (or trials) left out, each with the reason
};

// Cluster index of each value: sorted, a new cluster where the gap to the next exceeds `gap` (the held angles of a
// sweep, the pressure levels of a tensile test).
std::vector<int> clusters(const std::vector<double>& values, double gap);
// [deg] held angles further apart than this are different set angles (a held angle's own jitter is smaller).
inline constexpr double kHeldAngleGapDeg = 2.5;
// [deg] a sweep's reading further than this from the mean of its held angle is another set angle: twice the clusters'
// gap, as a measured held angle scatters (1 deg on the catalogue's rig) and a reading up to 5 deg from its held angle's
// mean is still that set angle. Set angles a rig steps through are further apart (the paper's 22.5 deg); set angles
// under 5 deg apart read as one.
inline constexpr double kSetAngleStepDeg = 2.0 * kHeldAngleGapDeg;
// The set angle of each of one muscle's sweep readings [deg], numbered in increasing angle: the clusters of
// kHeldAngleGapDeg, neighbours merged while a cluster's mean lies within kSetAngleStepDeg of the set angle's mean so
// far. The rule set_sweep_motion applies in the log's order, applied to the sorted readings: a jittered reading that
// clusters apart stays its set angle's.
std::vector<int> set_angle_clusters(const std::vector<double>& angles_deg);
// [kPa] a sweep's pressure levels further apart than this are different levels (a regulated level's jitter is smaller).
inline constexpr double kSweepLevelGapKpa = 5.0;

// Every log (a <name>.json sidecar of format softwrist.log/1 beside its <name>.csv) under `dir`, recursively, in
// path order. Logs of kinds without measurements to compare (design optimization) are listed as problems; a CSV
// without a sidecar too, with the import command that makes one. Throws only when `dir` is not a directory.
RealData load_real_data(const std::filesystem::path& dir);

// The trials of one log; throws std::runtime_error naming the file, line and column of a problem (or the sidecar's
// field of a convention it cannot read). A relative placement in the sidecar starts from `log_dir`.
std::vector<Trial> read_trials(const std::filesystem::path& sidecar, const std::string& name);
std::vector<Trial> trials_from_log(const experiments::TrialLog& log, const std::string& name,
                                   const std::filesystem::path& log_dir = ".");

}  // namespace softwrist::diagnosis
