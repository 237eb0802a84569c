#pragma once
// One local search within bounds (NLopt), with one policy for how it ends, shared by the design optimization and the
// gap diagnosis's effect fits.
//
// Ends:
//  - converged (x or f tolerance) or the evaluation budget spent: the best point, stopped_by empty;
//  - NLopt's roundoff-limited end or its generic failure: the best point evaluated so far (the search cannot do
//    better from there), stopped_by says which;
//  (the best point is NLopt's own: of points with equal values, it keeps the later one)
//  - an exception thrown by the objective: the search stops and the exception reaches the caller unchanged (an
//    objective that can meet infeasible points returns a large value instead, as the diagnosis's does);
//  - invalid settings (bounds, start, steps): std::invalid_argument naming the setting, before any evaluation.

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace softwrist::optimize {

enum class LocalAlgorithm { kNelderMead, kSubplex, kBobyqa };

struct BoundedSearchSettings {
  LocalAlgorithm algorithm = LocalAlgorithm::kBobyqa;
  std::vector<double> lower, upper;  // bounds, one per parameter
  std::vector<double> initial_step;  // empty: NLopt's default
  double x_tolerance_abs = 0.0;      // 0: not used
  double f_tolerance_rel = 0.0;      // 0: not used
  int max_evaluations = 1000;
};

struct BoundedSearchResult {
  std::vector<double> x;  // the best point NLopt evaluated
  double value = 0.0;     // the objective there
  int evaluations = 0;
  std::string stopped_by;  // empty, "roundoff-limited" or "NLopt failure"
};

using Objective = std::function<double(std::span<const double> x)>;

// Minimises `objective` from `start` (clamped into the bounds).
BoundedSearchResult minimize_bounded(const Objective& objective, std::vector<double> start,
                                     const BoundedSearchSettings& settings);

}  // namespace softwrist::optimize
