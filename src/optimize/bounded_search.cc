#include "optimize/bounded_search.h"

#include <algorithm>
#include <exception>
#include <stdexcept>

#include <nlopt.hpp>

namespace softwrist::optimize {
namespace {

nlopt::algorithm nlopt_algorithm(LocalAlgorithm algorithm) {
  switch (algorithm) {
    case LocalAlgorithm::kNelderMead:
      return nlopt::LN_NELDERMEAD;
    case LocalAlgorithm::kSubplex:
      return nlopt::LN_SBPLX;
    case LocalAlgorithm::kBobyqa:
      break;
  }
  return nlopt::LN_BOBYQA;
}

void check(const BoundedSearchSettings& s, std::size_t n) {
  if (n == 0) throw std::invalid_argument("bounded search: no parameters");
  if (s.lower.size() != n || s.upper.size() != n) throw std::invalid_argument("bounded search: bounds of another size");
  if (!s.initial_step.empty() && s.initial_step.size() != n) {
    throw std::invalid_argument("bounded search: initial steps of another size");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!(s.lower[i] <= s.upper[i])) throw std::invalid_argument("bounded search: a lower bound above its upper bound");
  }
  if (s.max_evaluations < 1) throw std::invalid_argument("bounded search: max_evaluations must be at least 1");
}

// What the objective wrapper keeps between NLopt's calls.
struct Progress {
  const Objective* objective;
  int evaluations = 0;
  std::exception_ptr error;
};

double call_objective(unsigned n, const double* x, double*, void* data) {
  auto* p = static_cast<Progress*>(data);
  try {
    const double value = (*p->objective)(std::span<const double>(x, n));
    ++p->evaluations;
    return value;
  } catch (...) {
    p->error = std::current_exception();
    throw nlopt::forced_stop();
  }
}

}  // namespace

BoundedSearchResult minimize_bounded(const Objective& objective, std::vector<double> start,
                                     const BoundedSearchSettings& settings) {
  const std::size_t n = start.size();
  check(settings, n);
  for (std::size_t i = 0; i < n; ++i) start[i] = std::clamp(start[i], settings.lower[i], settings.upper[i]);
  nlopt::opt search(nlopt_algorithm(settings.algorithm), static_cast<unsigned>(n));
  search.set_lower_bounds(settings.lower);
  search.set_upper_bounds(settings.upper);
  if (!settings.initial_step.empty()) search.set_initial_step(settings.initial_step);
  if (settings.x_tolerance_abs > 0.0) search.set_xtol_abs(settings.x_tolerance_abs);
  if (settings.f_tolerance_rel > 0.0) search.set_ftol_rel(settings.f_tolerance_rel);
  search.set_maxeval(settings.max_evaluations);
  Progress progress{.objective = &objective, .evaluations = 0, .error = nullptr};
  search.set_min_objective(call_objective, &progress);
  // NLopt leaves its best point in `start` and its value in `value` however it ends (ties go to the later point).
  BoundedSearchResult result;
  double value = 0.0;
  try {
    search.optimize(start, value);
  } catch (const nlopt::roundoff_limited&) {
    result.stopped_by = "roundoff-limited";
  } catch (const nlopt::forced_stop&) {
    // Only the wrapper forces a stop, for the objective's exception, rethrown below.
  } catch (const std::runtime_error&) {  // NLOPT_FAILURE; invalid arguments and bad_alloc go through
    result.stopped_by = "NLopt failure";
  }
  if (progress.error) std::rethrow_exception(progress.error);
  result.x = std::move(start);
  result.value = value;
  result.evaluations = progress.evaluations;
  return result;
}

}  // namespace softwrist::optimize
