#pragma once
// A trajectory's noise from its repetitions. Within one trial only the noise that changes faster than the motion
// can be told from the motion (replay.cc: the spread about a quadratic in 0.35 s windows), and real angle sensors
// wander slower than that: a fusion filter's correlated error, a gyro bias that drifts, a subject who rests a
// little differently each time (issue 20: the independent device's repeat-to-repeat spread is 5-18 times the
// windowed estimate). Repeated trials of one task show that noise whole: the model's error is common to the
// repetitions (each replayed with its own commands), the noise is not, so the spread of the nominal residuals
// across repetitions at each instant is the noise at every frequency, and the spread of their 1 s block means is
// what a block's mean residual carries (the group test's denominator; white noise would give noise^2 / n).
// A closed-loop task's repetitions differ in their commands, though, and the regulators answer each with the model's
// error: for the measured pressures, what the same muscle's command deviations predict is taken out first, and the
// spread is the mean over 1 s blocks but the outlying ones (a trial started while the regulators still move differs
// for its first seconds); the angles' deviations are left whole (the controller answers the IMUs' wander, so the
// commands carry it).
//
// Repetitions: trajectory trials of one rig and posture whose logged commands follow each other (their RMS
// difference is under kRepeatCommandSimilarity of their own spread about their mean), alike in length. A trial
// without repetitions takes the least such noise its sensors (rig, posture, angles or pressures) showed in a repeated
// task, where larger than its windowed estimate; with none, it keeps that estimate and the white-noise group test.

#include <vector>

#include "diagnosis/replay.h"

namespace softwrist::diagnosis {

// [1] commands whose RMS difference is under this fraction of their spread are the same task repeated (repetitions
// of a closed-loop task differ by 2-15 % on the independent device; different tasks by far more).
inline constexpr double kRepeatCommandSimilarity = 0.3;

// Sets of indices into `trials` (angles with angles, pressures with pressures) that repeat one task, each of two or
// more trials.
std::vector<std::vector<std::size_t>> repeat_sets(const std::vector<PreparedTrial>& trials);

// Raises the noise of each trial in each of `sets` (repeat_sets) to the repeat-to-repeat spread of its nominal
// residuals (`residuals[t]` aligned with trials[t].points; needed only for the sets' trials) where that is larger,
// and sets its group variance inflation and degrees of freedom from the spread of the 1 s block means; a trajectory
// in no set, from the quietest set read by the same sensors.
void apply_repeat_noise(std::vector<PreparedTrial>& trials, const std::vector<std::vector<std::size_t>>& sets,
                        const std::vector<std::vector<double>>& residuals);

// The gap test of one repeated task as a whole: its repetitions' mean residual, row by row, in the first one's 1 s
// groups, against the variance a group mean of `set.size()` repetitions' independent noise has (each one's
// noise^2 * group_inflation / n, over their number; F test with the noise's degrees of freedom). The model's error is
// common to the repetitions and the noise is not (above): the mean keeps the one whole and cuts the other's variance
// by the number of repetitions, where each repetition's own test weighs the error against its whole noise. An IMU
// 0.1-0.3 s late leaves 2-3 noise units in each of three repetitions, which a noise estimated from three (6 degrees of
// freedom) cannot tell from noise one by one (the independent device's seed 43: p 0.003-0.013 per repetition).
struct RepeatMeanTest {
  double p_value = 1.0;
  // The mean's systematic residual in the repetitions' noise units: sqrt(max(0, mean (r_mean/sigma)^2 - 1/K)) for K
  // repetitions, their common error's estimate (each repetition's own excess carries its noise's wander too).
  double excess = 0.0;
};
RepeatMeanTest repeat_mean_test(const std::vector<PreparedTrial>& trials,
                                const std::vector<std::vector<double>>& residuals, const std::vector<std::size_t>& set);

}  // namespace softwrist::diagnosis
