#pragma once
// Whether a gap drifts over the session. Every catalogue effect is a constant property of the device (a stiffness, a
// radius, a time constant), so once it is fitted the same condition measured again later must read the same within
// the noise. A fabric that creeps over a day of trials, a sensor that warms up or a strap that slips under load make
// the last repetition of a condition differ from the first in one direction: no constant effect can close that, so
// the verdict names none of them.
//
// The test is on the corrected model's residuals at each repeated condition (a repeat group, e.g. one pressure,
// direction and contraction step of a tensile test), the last repetition less the first: their mean, its size in
// noise units of one measurement, and its t statistic with the standard error from batch means (the conditions in
// the log's order cut into five contiguous batches; Law & Kelton's batch means). Batches, not the conditions' own
// scatter, because a real sensor's noise wanders over neighbouring conditions (a load cell's slow drift within a
// cycle): the differences of neighbours are then alike and their scatter understates the mean's uncertainty. With a
// middle repetition the batch means' scatter is taken from the contrast last - w middle + (w - 1) first, which a
// drift linear in time leaves at zero: a drift that differs from condition to condition (a creep that depends on the
// pressure) does not then inflate its own standard error.

#include <string>
#include <vector>

#include "diagnosis/replay.h"

namespace softwrist::diagnosis {

struct TrialDrift {
  std::string experiment;
  int first_repetition = 0, last_repetition = 0;
  std::size_t conditions = 0;  // repeat groups measured in both
  double shift = 0.0;          // mean of (last - first) residual, in noise units of one measurement
  double t = 0.0;              // that mean over its standard error
  bool significant = false;
};

struct DriftOptions {
  // For the standard error: five batches, long enough (68 conditions of a 340-condition tensile test) that a sensor's
  // wander over tens of neighbouring conditions leaves their means nearly independent.
  std::size_t batches = 5;
  std::size_t min_conditions = 10;  // two per batch at least
  double min_t = 8.6;               // Student's t with 4 degrees of freedom: two-sided chance 2e-4 per trial
  double min_shift = 0.5;           // [noise units] a drift below half a measurement's noise is not the gap's cause
};

// One entry per trial whose points carry repetitions (tensile cycles, range-of-motion and sweep repetitions) and that
// has at least two of them; `predictions` aligned with each trial's points.
std::vector<TrialDrift> drift_across_repetitions(const std::vector<PreparedTrial>& prepared,
                                                 const std::vector<std::vector<double>>& predictions,
                                                 const DriftOptions& options = {});

}  // namespace softwrist::diagnosis
