#pragma once
// Whether the device changed during one setting of a torque sweep. A sweep measures every pressure at a held angle
// (a setting: the hand fixed on the plate at that angle) and repeats the whole sweep; a constant property of the
// device, hysteresis included, makes the repeats of one condition differ in the same way at every loaded setting, and
// the hand's seat, re-made at each setting, shifts all of a setting's conditions alike. A strap that slips the first
// time the tension beats its grip, a re-seated band or a knocked plate changes the device part-way through one
// setting instead: there the repeat difference varies from one pressure to the next far more than at the others.
//
// Per condition (Point::condition) measured in the first and the last repetition, the difference of a stateless
// model's residuals (last - first; the diagnosis passes the nominal's, so that a fitted hysteresis's own start-up
// transient is not read as a change); per setting (Point::unit), the variance of those differences about the
// setting's own mean, which the hand's seat does not move. The setting whose variance is largest is compared with the
// median of the other settings' of the same muscle (robust to a second odd setting, and to the unloaded settings whose
// differences are the sensor's noise alone as long as they are not the majority); a sweep of several muscles reports
// the muscle whose ratio is largest.

#include <cstddef>
#include <string>
#include <vector>

#include "diagnosis/replay.h"

namespace softwrist::diagnosis {

struct SettingChange {
  std::string experiment;
  std::string muscle;      // the setting's muscle
  double angle_deg = 0.0;  // the held angle of the setting whose repeats disagree most
  // Settings with enough conditions measured in both repetitions, and (once that setting is found) whose repeats
  // differ at all, that setting included.
  std::size_t settings = 0;
  std::size_t conditions = 0;  // conditions at that setting
  int first_repetition = 0, last_repetition = 0;
  // Standard deviation of that setting's repeat differences about their mean, in the trial's unit and in noise units
  // of one measurement.
  double spread = 0.0, spread_noise_units = 0.0;
  std::string unit;
  double ratio = 0.0;  // their variance over the median of the other settings'
  bool significant = false;
};

struct SettingChangeOptions {
  std::size_t min_settings = 4;    // the setting and at least three others for the median
  std::size_t min_conditions = 3;  // per setting: a variance with two degrees of freedom at least
  // Calibrated on the development seeds 21-27 of the independent benchmark (docs/diagnosis.md, "A change during one
  // setting"): on their 189 sweeps the largest ratio without a change was 13.4 (a wrap's steepest angle, where a
  // regulator's unlogged pressure error moves the torque most) and the smallest with a slipping strap 42.
  double min_ratio = 25.0;
};

// One entry per trial whose points carry conditions (torque sweeps) in at least two repetitions; `predictions`
// aligned with each trial's points.
std::vector<SettingChange> change_at_one_setting(const std::vector<PreparedTrial>& prepared,
                                                 const std::vector<std::vector<double>>& predictions,
                                                 const SettingChangeOptions& options = {});

}  // namespace softwrist::diagnosis
