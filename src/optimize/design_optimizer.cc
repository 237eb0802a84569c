#include "optimize/design_optimizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "common/parallel_for.h"
#include "optimize/bounded_search.h"
#include "physics/errors.h"

namespace softwrist::optimize {
namespace {

using physics::Placement;

std::array<double, 4> to_array(const Placement& p) { return {p.d1, p.w1, p.d2, p.w2}; }
Placement to_placement(const double* x) { return {.d1 = x[0], .w1 = x[1], .d2 = x[2], .w2 = x[3]}; }

std::vector<double> axis_values(double lower, double upper, double step) {
  if (!(step > 0.0)) throw physics::InvalidParameter("start resolution must be positive");
  std::vector<double> values;
  for (int i = 0;; ++i) {
    const double value = lower + i * step;
    if (value > upper + 1e-9 * step) break;
    values.push_back(std::min(value, upper));
  }
  if (upper - values.back() > 1e-9 * step) values.push_back(upper);
  return values;
}

LocalAlgorithm algorithm_named(const std::string& name) {
  if (name == "neldermead") return LocalAlgorithm::kNelderMead;
  if (name == "subplex") return LocalAlgorithm::kSubplex;
  throw physics::InvalidParameter("unknown optimizer algorithm '" + name + "' (neldermead, subplex)");
}

}  // namespace

void validate(const OptimizerOptions& options) {
  (void)algorithm_named(options.algorithm);
  const auto r = to_array(options.start_resolution);
  for (double step : r) {
    if (!(step > 0.0)) throw physics::InvalidParameter("start resolution must be positive");
  }
  if (!(options.x_tolerance > 0.0)) throw physics::InvalidParameter("x tolerance must be positive");
  if (options.max_evaluations < 1) throw physics::InvalidParameter("max evaluations must be at least 1");
}

std::vector<Placement> start_grid(const PlacementBounds& bounds, const Placement& resolution) {
  std::vector<Placement> grid;
  for (double d1 : axis_values(bounds.lower.d1, bounds.upper.d1, resolution.d1)) {
    for (double w1 : axis_values(bounds.lower.w1, bounds.upper.w1, resolution.w1)) {
      for (double d2 : axis_values(bounds.lower.d2, bounds.upper.d2, resolution.d2)) {
        for (double w2 : axis_values(bounds.lower.w2, bounds.upper.w2, resolution.w2)) {
          grid.push_back({.d1 = d1, .w1 = w1, .d2 = d2, .w2 = w2});
        }
      }
    }
  }
  return grid;
}

LocalSolution optimize_from(const DesignProblem& problem, const Placement& start, const OptimizerOptions& options,
                            double pressure) {
  const DesignEvaluator evaluator(problem, pressure);
  const auto lower = to_array(problem.bounds.lower), upper = to_array(problem.bounds.upper);
  // First simplex: half the start resolution, so the first steps explore the cell around the start.
  const auto resolution = to_array(options.start_resolution);
  std::vector<double> step(4);
  for (int i = 0; i < 4; ++i) step[i] = std::max(0.5 * resolution[i], 10 * options.x_tolerance);
  const auto s = to_array(start);
  const BoundedSearchResult found =
      minimize_bounded([&](std::span<const double> x) { return evaluator.objective(to_placement(x.data())); },
                       std::vector<double>(s.begin(), s.end()),
                       {.algorithm = algorithm_named(options.algorithm),
                        .lower = std::vector<double>(lower.begin(), lower.end()),
                        .upper = std::vector<double>(upper.begin(), upper.end()),
                        .initial_step = step,
                        .x_tolerance_abs = options.x_tolerance,
                        .max_evaluations = options.max_evaluations});
  return {.start = start,
          .placement = to_placement(found.x.data()),
          .objective = found.value,
          .evaluations = found.evaluations};
}

std::vector<LocalSolution> optimize_starts(const DesignProblem& problem, const std::vector<Placement>& starts,
                                           const OptimizerOptions& options, double pressure,
                                           const std::function<void(int)>& progress) {
  validate(problem);
  std::vector<LocalSolution> solutions(starts.size());
  parallel_for(
      static_cast<int>(starts.size()), options.jobs,
      [&](int i) { solutions[i] = optimize_from(problem, starts[i], options, pressure); }, progress);
  return solutions;
}

DesignResult best_of(const std::vector<LocalSolution>& solutions) {
  if (solutions.empty()) throw std::invalid_argument("best_of: no solutions");
  DesignResult result;
  result.best = solutions.front();
  for (const auto& s : solutions) {
    result.evaluations += s.evaluations;
    if (s.objective < result.best.objective) result.best = s;
  }
  result.starts = static_cast<int>(solutions.size());
  return result;
}

DesignResult optimize_design(const DesignProblem& problem, const OptimizerOptions& options) {
  return best_of(
      optimize_starts(problem, start_grid(problem.bounds, options.start_resolution), options, problem.pressure));
}

LocalSolution exhaustive_search(const DesignProblem& problem, const Placement& resolution, int jobs) {
  const std::vector<Placement> grid = start_grid(problem.bounds, resolution);
  const DesignEvaluator evaluator(problem);
  std::vector<double> values(grid.size());
  parallel_for(static_cast<int>(grid.size()), jobs, [&](int i) { values[i] = evaluator.objective(grid[i]); });
  const auto best = std::min_element(values.begin(), values.end()) - values.begin();
  return {.start = grid[best],
          .placement = grid[best],
          .objective = values[best],
          .evaluations = static_cast<int>(grid.size())};
}

PressureResult minimum_pressure(const DesignProblem& problem, const OptimizerOptions& options,
                                const PressureSearch& search) {
  validate(problem);
  if (!(search.low > 0.0) || !(search.high > search.low) || !(search.tolerance > 0.0)) {
    throw physics::InvalidParameter("pressure search: needs 0 < low < high and a positive tolerance");
  }
  const std::vector<Placement> grid = start_grid(problem.bounds, options.start_resolution);
  PressureResult result;
  // The best design at one pressure, judged by its largest deficit.
  const auto design_at = [&](double pressure) {
    const DesignEvaluator evaluator(problem, pressure);
    std::vector<double> screened(grid.size());
    for (std::size_t i = 0; i < grid.size(); ++i) screened[i] = evaluator.objective(grid[i]);
    std::vector<std::size_t> order(grid.size());
    std::iota(order.begin(), order.end(), 0);
    const std::size_t keep = std::min<std::size_t>(std::max(1, search.screened_starts), grid.size());
    std::partial_sort(order.begin(), order.begin() + keep, order.end(),
                      [&](auto a, auto b) { return screened[a] < screened[b]; });
    std::vector<Placement> starts;
    for (std::size_t i = 0; i < keep; ++i) starts.push_back(grid[order[i]]);
    const LocalSolution best = best_of(optimize_starts(problem, starts, options, pressure)).best;
    const double deficit = evaluator.max_deficit(best.placement);
    result.trace.emplace_back(pressure, deficit);
    return std::pair{best, deficit <= search.deficit_tolerance};
  };
  auto [high_design, high_meets] = design_at(search.high);
  if (!high_meets) return result;
  double low = search.low, high = search.high;
  LocalSolution best = high_design;
  if (auto [low_design, low_meets] = design_at(low); low_meets) {
    result.found = true;
    result.pressure = low;
    result.design = low_design;
    return result;
  }
  while (high - low > search.tolerance) {
    const double middle = 0.5 * (low + high);
    auto [design, meets] = design_at(middle);
    if (meets) {
      high = middle;
      best = design;
    } else {
      low = middle;
    }
  }
  result.found = true;
  result.pressure = high;
  result.design = best;
  return result;
}

}  // namespace softwrist::optimize
