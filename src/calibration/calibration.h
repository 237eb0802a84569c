#pragma once
// Calibrating the exosuit from its own sensors (softwrist calibrate, docs/calibration.md): the excitation routine
// (control/excitation_controller.h) runs through the bridge, the gap diagnosis fits the effects the routine's data
// identify on top of the nominal placement, and the corrected model becomes the calibrated placement file that the
// model-based controller takes (`--model`, the tracking config's `model`).
//
// Only IMU angles and measured pressures are recorded (no torque sensor, no motion capture), so only effects that
// change those are identifiable; the rest are named with the reason (unidentifiable_effects). Each identified
// parameter comes with a 95 % interval (diagnosis/parameter_intervals.h).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bridge/bridge_plant.h"
#include "diagnosis/diagnosis.h"
#include "diagnosis/parameter_intervals.h"
#include "experiments/experiment.h"
#include "sim/device.h"

namespace softwrist::calibration {

// The catalogue's effects the routine's data can tell apart: the regulators' lag (the measured pressures' edges),
// the mounts' stretching and the relaxed wrist (where each muscle settles at three forces), the fabric's hysteresis
// (the ramps up and down).
std::vector<diagnosis::EffectId> identifiable_effects();

struct Unidentifiable {
  std::string effect, reason;
};
// The others, each with why the routine's sensors cannot see it.
std::vector<Unidentifiable> unidentifiable_effects();

// What the routine did on the device.
struct RoutineRecord {
  std::filesystem::path log_dir;
  double planned_s = 0.0, run_s = 0.0;  // the routine's length and how much of it ran
  std::optional<std::string> fault;     // what stopped it (the device was vented)
  std::vector<std::string> parts_not_run;
};

// Runs the routine `config` (a tracking experiment whose controller is "excitation") on `plant`, logging into
// `log_dir` as a hardware trial. A fault ends it vented and is recorded, not thrown. Throws std::runtime_error for a
// config that is not an excitation routine, before anything moves.
RoutineRecord run_routine(const experiments::ExperimentConfig& config, bridge::BridgePlant& plant,
                          const std::filesystem::path& log_dir, bool overwrite = false);

// calibration.json's "routine": the log, planned and run length, fault, parts not run.
nlohmann::json to_json(const RoutineRecord& routine);

struct CalibrationOptions {
  int jobs = 2;
  int bootstrap = 100;
  // A parameter counts as identified when its 95 % interval is narrower than this fraction of its range in the
  // catalogue (ParameterInterval::relative_width).
  double identified_width = 0.25;
  int refit_evaluations = 80;  // the joint refit's replays (diagnosis/joint_refit.h)
};

struct Calibration {
  diagnosis::Diagnosis diagnosis;
  sim::DeviceDescription calibrated;  // the nominal with the fitted effects applied
  std::vector<diagnosis::ParameterInterval> parameters;
  std::vector<std::string> effects_applied;    // the effects that improved the fit, in the order they joined
  std::vector<Unidentifiable> not_identified;  // effects or parameters the data left open, with why
  std::vector<std::string> not_in_placement;   // fitted values a placement file cannot hold (the dead time)
};

// Identifies the device from the logs under `log_dir` against the nominal placement.
Calibration calibrate_from_logs(const std::filesystem::path& log_dir, const sim::DeviceDescription& nominal,
                                const CalibrationOptions& options);

// DIR/calibrated.json (the placement file), DIR/calibration.json (what was identified, with intervals, what was not,
// the routine's record) and the diagnosis's report under DIR/diagnosis/. Returns calibration.json's content.
nlohmann::json write_calibration(const Calibration& calibration, const RoutineRecord& routine,
                                 const std::filesystem::path& dir, double wall_s);

}  // namespace softwrist::calibration
