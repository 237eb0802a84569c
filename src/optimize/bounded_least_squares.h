#pragma once
// Bounded nonlinear least squares: Levenberg-Marquardt on a finite-difference Jacobian, with the bounds kept by an
// active set (a parameter whose step would leave its box is held at the bound and the step is solved again for the
// rest). For residuals that cost a simulation each, where the derivative-free searches (bounded_search.h) spend
// 2n+1 evaluations only to build their first model: here one Jacobian costs n (n + 1 on difference_residuals), and
// its columns are independent, so they are evaluated on `jobs` threads.
//
// The residual function may be called from several threads at once. It returns std::nullopt where the parameters are
// infeasible (a failed simulation): a Jacobian column then takes the step the other way, and a trial step there is
// rejected like one that does not decrease the cost, and the next step holds the parameter whose difference was
// infeasible where it is.

#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace softwrist::optimize {

using ResidualFunction = std::function<std::optional<std::vector<double>>(std::span<const double> x)>;

struct LeastSquaresSettings {
  std::vector<double> lower, upper;  // bounds, one per parameter (lower <= upper; equal bounds hold it)
  double difference_step = 0.02;     // forward-difference step, as a fraction of each box's width
  int max_evaluations = 100;         // residual evaluations, the Jacobians' included
  int jobs = 1;                      // threads for a Jacobian's columns
  double cost_tolerance_rel = 1e-4;  // stop when an accepted step lowers the cost by less than this fraction
  // After the first Jacobian, update it by Broyden's rank-one formula from each step taken instead of differencing it
  // again (the secant Levenberg-Marquardt method of Madsen, Nielsen & Tingleff 2004, "Methods for non-linear least
  // squares problems", Sec. 3.4): one evaluation per iteration instead of n + 1. It is differenced again where a
  // step on it fails or stalls, so the fit stops on a differenced model unless the budget runs out first. The
  // bounds fenced by a differencing (infeasible directions) stay as they were until the next one. For residuals close
  // to linear in the parameters (a fit within small tolerances), where after the first step the differences relearn
  // little.
  bool secant_updates = false;
  // Parameters whose Jacobian columns are cheap to evaluate right after the point itself (a caller's cache keeps
  // what they do not change): evaluated first, on the calling thread.
  std::vector<bool> cheap;
  // Where set, the Jacobian is differenced on these residuals instead, its base point included: a cheaper
  // approximation of the residuals whose error varies smoothly with the parameters (a simulation at a coarser step),
  // so that it cancels in a difference. Only the search direction comes from it; every cost compared, every step
  // accepted and the point returned are the residuals' own. Where it is infeasible at the base point, the residuals
  // are differenced; where it is infeasible at a point of a column, that column is differenced again on the
  // residuals (if the budget allows two evaluations per such column; otherwise its direction stays fenced). Called
  // from several threads at once, as the residuals are; its evaluations count towards max_evaluations.
  ResidualFunction difference_residuals;
};

struct LeastSquaresResult {
  std::vector<double> x;  // the best point evaluated
  double cost = 0.0;      // sum of squared residuals there
  int evaluations = 0;    // of the residuals and of difference_residuals
  int iterations = 0;     // Jacobians computed by differences
};

// Minimises the sum of squared residuals from `start` (clamped into the bounds). Throws std::invalid_argument for
// inconsistent settings and std::runtime_error when the start itself is infeasible.
LeastSquaresResult minimize_least_squares(const ResidualFunction& residuals, std::vector<double> start,
                                          const LeastSquaresSettings& settings);

}  // namespace softwrist::optimize
