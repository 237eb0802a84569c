#pragma once
// How well the data pin down the corrected model's fitted parameters: a 95 % interval for each parameter of the
// diagnosis's combination (Diagnosis::combination), from the Jacobian of the noise-weighted residuals at the fit
// (the Gauss-Newton covariance s^2 (J^T J)^-1, with s^2 the residuals' own mean square, so a model that misses widens
// it), widened for residuals correlated in time (a trajectory's consecutive samples are not independent: the AR(1)
// factor (1 + rho) / (1 - rho) of the most correlated trial). A parameter the data do not constrain (a flat
// direction of J^T J) gets an interval spanning its whole range. Intervals are taken in the space the fits search
// (log space for stiffnesses), so they respect the parameter's bounds.

#include <string>
#include <vector>

#include "diagnosis/diagnosis.h"
#include "diagnosis/replay.h"

namespace softwrist::diagnosis {

struct ParameterInterval {
  std::string effect, name;  // the effect and its parameter, named with the unit (effects.h)
  double value = 0.0;        // fitted
  double low = 0.0, high = 0.0;
  // The interval's width as a fraction of the parameter's range in the catalogue (in the searched space): near 0
  // well determined, 1 not at all.
  double relative_width = 1.0;
};

// The intervals of every parameter of `d`'s combination, replaying its data with `engine` (2 replays per parameter).
// `nominal` is the device the diagnosis was given. Empty when nothing was combined.
std::vector<ParameterInterval> combination_intervals(const Diagnosis& d, const sim::DeviceDescription& nominal,
                                                     ReplayEngine& engine);

}  // namespace softwrist::diagnosis
