#pragma once
// The moments of a run worth drawing, read from its trial log (docs/log-format.md): the wrist's angles and the four
// muscles' pressures at each, and the camera that shows them (radial view for flexion/extension, palmar view for
// ulnar/radial deviation, as the paper's Fig. Overview).
//   range_of_motion      each muscle's settled pose at its pressure (first repetition)
//   torque_validation    the held angle and pressure of the largest measured torque
//   tracking             one case's most flexed and most extended instants (and most ulnar and most radial when it
//                        moves that axis), or the instant nearest a chosen time
//   design_optimization  none: the run holds no wrist pose

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "report/offscreen_renderer.h"
#include "sim/device.h"

namespace softwrist::report {

struct WristPose {
  double fe = 0.0, ur = 0.0;              // [rad], flexion and ulnar deviation positive
  std::array<double, 4> pressures_kpa{};  // flexor, extensor, ulnar, radial
};

struct Moment {
  std::string name;     // file-name friendly: "rom_flexor", "case0_most_flexed", "case0_t12.50_radial"
  std::string caption;  // what the picture shows, in the paper's terms
  WristPose pose;
  View view = View::kRadial;
};

struct TimedPose {
  double t = 0.0;  // [s] from the start of the case
  WristPose pose;
};

struct RunMoments {
  sim::DeviceDescription device;  // the device the run simulated (its config's "model"; else the paper's device)
  std::vector<Moment> moments;
};

struct MomentQuery {
  std::optional<double> at_s;  // tracking runs: the instant nearest this time instead of the extremes
  int case_index = -1;         // tracking runs: which case (controller and repetition) of the log; -1 the first
};

// Throws std::runtime_error naming the problem: not a run directory, a log with missing columns, --at on a run
// that is not a tracking run, a case the log does not hold, a time outside the case.
RunMoments run_moments(const std::filesystem::path& run_dir, const MomentQuery& query = {});

// A tracking case's poses in time order, one per logged control tick (the joint angles where the log has them,
// else the IMU angles; the commanded pressures). Throws for a run of another kind or a case the log does not hold.
std::vector<TimedPose> tracking_timeline(const std::filesystem::path& run_dir, int case_index = -1);

// The device a run simulated.
sim::DeviceDescription run_device(const std::filesystem::path& run_dir);

}  // namespace softwrist::report
