#pragma once
// The scatter a torque sweep's readings share within one setting. On a torque rig the hand is seated on the plate
// and the relaxed wrist settles once per held angle; every pressure read there shares that seat's angle error and
// that moment's muscle tone, so the readings of one setting are not independent: a relaxed wrist's torque moves by
// tenths of a N m from one setting to the next (10-20 % of its stiffness, Formica et al., J. Neurophysiol. 2012)
// while the sensor's own noise is a few mN m. Weighed as independent readings, a setting's shared offset counted
// once per pressure, and a device that differs from its model by nothing but that scatter showed a gap in its sweep
// of 1.2-1.6 noise units within its tolerances on every development data set of the independent device (seeds
// 38-40) whose effect does not touch the sweep.
//
// The model of the noise is a random effect per setting: residual = offset of the setting (standard deviation
// `setting_scatter`) + the reading's own noise (`noise`). A setting's mean over n of its readings then has variance
// noise^2 / n + scatter^2, and scaling that mean by sqrt(noise^2 / (noise^2 + n scatter^2)), its deviations left
// whole, makes the residuals over `noise` white (generalised least squares for a compound-symmetric covariance;
// Searle, Casella & McCulloch, Variance Components, 1992, Ch. 3). What one setting's readings share is then weighed
// by the settings it was seen in, what differs from one pressure to the next by the sensor's noise as before.

#include <vector>

#include "diagnosis/replay.h"

namespace softwrist::diagnosis {

// [1] The one-sided confidence at whose upper end a setting scatter estimated from a handful of settings is taken
// (estimate_setting_scatter): at the estimate itself a right model's sweep failed the 1 % gap test 10 times in 400.
inline constexpr double kSettingScatterConfidence = 0.75;

// The points of a trial whose settings are whitened together: all, or one part of the training / held-out split (a
// setting's mean over the training points alone must not borrow the held-out ones).
enum class SplitPart { kAll, kTraining, kHeldOut };

// Sets `trial.setting_scatter` (and says how in `noise_source`) from the nominal's `residuals` (one per point) of a
// trial whose points name their setting (Point::setting), its `noise` already estimated: where a held angle was set
// more than once (repetitions), from the spread of its settings' mean residuals; otherwise from the settings' means
// about a quadratic in angle per muscle and repetition (a model error smooth in angle, a relaxed wrist's stiffness,
// does not count as scatter). The variance at the upper end of its one-sided 75 % interval, less the reading
// noise's share of a setting's mean, floored at 0. Left 0 where no setting holds two readings or the settings give
// fewer than two degrees of freedom.
void estimate_setting_scatter(PreparedTrial& trial, const std::vector<double>& residuals);

// `residuals` (one per point of `trial`, in its unit) with each setting's mean over the points of `part` scaled by
// sqrt(noise^2 / (noise^2 + n scatter^2)), n its points in the part; points outside the part, or of no setting,
// unchanged. The identity where the trial has no setting scatter.
std::vector<double> whitened(const PreparedTrial& trial, std::vector<double> residuals,
                             SplitPart part = SplitPart::kAll);

}  // namespace softwrist::diagnosis
