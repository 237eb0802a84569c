#pragma once
// Multi-start design optimization (Section Parameter optimization): a bounded local search from every point of the
// initial-guess grid of Table optimized_parameters, the best result kept. The paper used a bounded fminsearch
// (Nelder-Mead) in MATLAB; here NLopt's bounded Nelder-Mead or Subplex. Plus the exhaustive grid search that checks
// it, and the search for the smallest pressure at which an optimized design meets the reference everywhere.

#include <functional>
#include <string>
#include <vector>

#include "optimize/design_problem.h"
#include "physics/exosuit_layout.h"

namespace softwrist::optimize {

struct OptimizerOptions {
  physics::Placement start_resolution = kPaperStartResolution;  // [m]
  std::string algorithm = "neldermead";                         // "neldermead" (as the paper's fminsearch) or "subplex"
  double x_tolerance = 1e-5;                                    // [m], absolute, per placement parameter
  int max_evaluations = 4000;                                   // per start
  int jobs = 1;                                                 // threads
};

// Throws physics::InvalidParameter for an unknown algorithm or a non-positive resolution or tolerance.
void validate(const OptimizerOptions& options);

struct LocalSolution {
  physics::Placement start;
  physics::Placement placement;
  double objective = 0.0;  // [N m]
  int evaluations = 0;
};

struct DesignResult {
  LocalSolution best;
  long evaluations = 0;  // over all starts
  int starts = 0;
};

// The grid of initial guesses: each parameter from its lower bound in steps of the resolution, plus the upper
// bound if the steps miss it (Table optimized_parameters: 11 x 4 x 16 x 5 = 3520 starts).
std::vector<physics::Placement> start_grid(const PlacementBounds& bounds, const physics::Placement& resolution);

// One bounded local search from `start`.
LocalSolution optimize_from(const DesignProblem& problem, const physics::Placement& start,
                            const OptimizerOptions& options, double pressure);

// Local searches from every start (on options.jobs threads), in the order of `starts`; `progress` (optional) is
// called with the number of finished starts, from the calling thread.
std::vector<LocalSolution> optimize_starts(const DesignProblem& problem, const std::vector<physics::Placement>& starts,
                                           const OptimizerOptions& options, double pressure,
                                           const std::function<void(int)>& progress = {});

// The lowest objective of `solutions` (the first of equals, so the result does not depend on the thread count).
DesignResult best_of(const std::vector<LocalSolution>& solutions);

// The full multi-start at the problem's pressure.
DesignResult optimize_design(const DesignProblem& problem, const OptimizerOptions& options);

// The best point of a grid over the bounds at `resolution` (no local search): the slower, exhaustive check.
LocalSolution exhaustive_search(const DesignProblem& problem, const physics::Placement& resolution, int jobs);

struct PressureSearch {
  double low = physics::kRegulatorMaxPressure;  // [Pa], start of the bracket
  double high = 600e3;       // [Pa], end of the bracket (the fPAM's burst pressure is about 448 kPa for r0 = 1.23 cm)
  double tolerance = 500.0;  // [Pa], bracket width to stop at
  int screened_starts = 16;  // local searches per trial pressure, from the best grid points
  double deficit_tolerance = 1e-6;  // [N m], max deficit that still counts as meeting the reference
};

struct PressureResult {
  bool found = false;                            // false when even `high` does not meet the reference
  double pressure = 0.0;                         // [Pa], the smallest pressure found that meets it (within tolerance)
  LocalSolution design;                          // the optimized placement at that pressure
  std::vector<std::pair<double, double>> trace;  // (pressure, best max deficit [N m]) at each trial
};

// Bisection on the pressure for the smallest one at which an optimized placement has no deficit anywhere. At each
// trial pressure the objective is screened on the start grid and local searches run from the best screened points.
PressureResult minimum_pressure(const DesignProblem& problem, const OptimizerOptions& options,
                                const PressureSearch& search);

}  // namespace softwrist::optimize
