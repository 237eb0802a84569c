#include "optimize/bounded_least_squares.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <stdexcept>

namespace softwrist::optimize {
namespace {

LeastSquaresSettings box(std::vector<double> lower, std::vector<double> upper, int budget = 200, int jobs = 1) {
  return {.lower = std::move(lower), .upper = std::move(upper), .max_evaluations = budget, .jobs = jobs};
}

// Rosenbrock's function as residuals (10 (y - x^2), 1 - x): minimum 0 at (1, 1), a curved valley.
std::optional<std::vector<double>> rosenbrock(std::span<const double> p) {
  return std::vector<double>{10.0 * (p[1] - p[0] * p[0]), 1.0 - p[0]};
}

TEST(BoundedLeastSquares, FindsTheMinimumOfACurvedValley) {
  const auto result = minimize_least_squares(rosenbrock, {-1.2, 1.0}, box({-2, -2}, {2, 2}));
  EXPECT_NEAR(result.x[0], 1.0, 1e-4);
  EXPECT_NEAR(result.x[1], 1.0, 1e-4);
  EXPECT_LT(result.cost, 1e-8);
  EXPECT_LE(result.evaluations, 200);
}

// A fit within tolerances, as the diagnosis's: 30 parameters, residuals close to linear in them (a weak quadratic
// term), the data 60 points, some parameters at their bounds at the minimum. Secant updates reach the differenced
// fit's minimum (29.5383 against 29.5386) with 131 evaluations against 193.
TEST(BoundedLeastSquares, SecantUpdatesFitANearlyLinearProblemWithFewerEvaluations) {
  constexpr int kParameters = 30, kPoints = 60;
  const auto model = [](std::span<const double> p) -> std::optional<std::vector<double>> {
    std::vector<double> r(kPoints);
    for (int i = 0; i < kPoints; ++i) {
      double y = 0.0;
      for (int k = 0; k < kParameters; ++k) {
        const double a = std::sin(0.37 * (i + 1) * (k + 1));
        y += a * p[static_cast<std::size_t>(k)] +
             0.05 * a * a * p[static_cast<std::size_t>(k)] * p[static_cast<std::size_t>(k)];
      }
      r[static_cast<std::size_t>(i)] = y - std::cos(0.11 * i);
    }
    return r;
  };
  const std::vector<double> lower(kParameters, -1.0), upper(kParameters, 1.0), start(kParameters, 0.0);
  LeastSquaresSettings settings = box(lower, upper, 400);
  const LeastSquaresResult differenced = minimize_least_squares(model, start, settings);
  settings.secant_updates = true;
  const LeastSquaresResult secant = minimize_least_squares(model, start, settings);
  EXPECT_LE(secant.cost, differenced.cost * 1.001 + 1e-9);
  EXPECT_LT(secant.evaluations, differenced.evaluations * 3 / 4)
      << secant.evaluations << " against " << differenced.evaluations;
  EXPECT_GE(secant.iterations, 2);     // the secant model stalled and was differenced again
  EXPECT_LT(secant.evaluations, 400);  // and the fit stopped there, not at the budget
}

TEST(BoundedLeastSquares, ABoundHoldsTheParameterItWouldPassAndTheOthersStillFit) {
  // r = (x - 3, y - x): unconstrained (3, 3); with x <= 1 the best is x = 1, y = 1.
  const auto linear = [](std::span<const double> p) -> std::optional<std::vector<double>> {
    return std::vector<double>{p[0] - 3.0, p[1] - p[0]};
  };
  const auto result = minimize_least_squares(linear, {0.0, 0.0}, box({-1, -5}, {1, 5}));
  EXPECT_DOUBLE_EQ(result.x[0], 1.0);
  EXPECT_NEAR(result.x[1], 1.0, 1e-6);
  EXPECT_NEAR(result.cost, 4.0, 1e-6);
}

TEST(BoundedLeastSquares, InfeasiblePointsAreSteppedAroundAndColumnsRunOnThreads) {
  // Infeasible beyond x = 0.5 (a simulation that fails there); the minimum of (x - 2)^2 + (y - 1)^2 within is x = 0.5.
  std::atomic<int> calls{0};
  const auto fenced = [&](std::span<const double> p) -> std::optional<std::vector<double>> {
    ++calls;
    if (p[0] > 0.5) return std::nullopt;
    return std::vector<double>{p[0] - 2.0, p[1] - 1.0, 0.1 * p[2]};
  };
  const auto result = minimize_least_squares(fenced, {0.0, 0.0, 1.0}, box({-1, -1, -1}, {1, 1, 1}, 200, 2));
  EXPECT_LE(result.x[0], 0.5);
  EXPECT_GT(result.x[0], 0.45);
  EXPECT_NEAR(result.x[1], 1.0, 1e-3);
  EXPECT_NEAR(result.x[2], 0.0, 1e-3);
  EXPECT_EQ(result.evaluations, calls.load());
}

// Rosenbrock's residuals with a smooth error added, as a simulation at a coarser step gives: a bias that moves its
// minimum to (1.05, 1.1) if it were minimised itself.
std::optional<std::vector<double>> coarse_rosenbrock(std::span<const double> p) {
  auto r = rosenbrock(p);
  (*r)[0] += 0.02 + 0.03 * p[0] - 0.04 * p[1];
  (*r)[1] += 0.05;
  return r;
}

TEST(BoundedLeastSquares, DifferencesOnACoarserModelStillEndAtTheResidualsOwnMinimum) {
  std::atomic<int> fine{0}, coarse{0};
  LeastSquaresSettings settings = box({-2, -2}, {2, 2}, 400, 2);
  settings.difference_residuals = [&](std::span<const double> p) {
    ++coarse;
    return coarse_rosenbrock(p);
  };
  const auto result = minimize_least_squares(
      [&](std::span<const double> p) {
        ++fine;
        return rosenbrock(p);
      },
      {-1.2, 1.0}, settings);
  EXPECT_NEAR(result.x[0], 1.0, 1e-3);  // the residuals' minimum, not the coarse model's
  EXPECT_NEAR(result.x[1], 1.0, 2e-3);
  EXPECT_LT(result.cost, 1e-6);
  EXPECT_EQ(coarse.load() % 3, 0);  // each Jacobian: its base point and two columns, all coarse
  EXPECT_EQ(result.iterations, coarse.load() / 3);
  EXPECT_EQ(result.evaluations, fine.load() + coarse.load());
}

TEST(BoundedLeastSquares, ACoarseModelInfeasibleWhereTheResidualsAreNotIsNotDifferenced) {
  // The coarse model fails beyond x = 0.5, the residuals do not: the minimum at (1, 1) is still found (a Jacobian
  // whose x column is fenced where the coarse model fails could not step past 0.5), with the Jacobians there
  // differenced on the residuals themselves, and those before on the coarse model.
  std::atomic<int> coarse{0};
  LeastSquaresSettings settings = box({-2, -2}, {2, 2}, 400);
  settings.difference_residuals = [&](std::span<const double> p) -> std::optional<std::vector<double>> {
    ++coarse;
    if (p[0] > 0.5) return std::nullopt;
    return coarse_rosenbrock(p);
  };
  const auto result = minimize_least_squares(rosenbrock, {-1.2, 1.0}, settings);
  EXPECT_NEAR(result.x[0], 1.0, 1e-3);
  EXPECT_NEAR(result.x[1], 1.0, 2e-3);
  EXPECT_GT(coarse.load(), 3);
}

TEST(BoundedLeastSquares, TheBudgetIsKeptWithACoarseModelThatFails) {
  // Every coarse Jacobian's x column fails and is differenced again on the residuals: the budget still holds.
  for (const int budget : {4, 5, 7, 12}) {
    LeastSquaresSettings settings = box({-2, -2}, {2, 2}, budget);
    settings.difference_residuals = [](std::span<const double> p) -> std::optional<std::vector<double>> {
      if (p[0] > -1.2) return std::nullopt;
      return coarse_rosenbrock(p);
    };
    const auto result = minimize_least_squares(rosenbrock, {-1.2, 1.0}, settings);
    EXPECT_LE(result.evaluations, budget) << "budget " << budget;
    EXPECT_LE(result.cost, 24.2 + 1e-12) << "budget " << budget;  // the start's at most
    if (budget >= 12) {
      EXPECT_LT(result.cost, 24.2);
    }
  }
}

TEST(BoundedLeastSquares, EqualBoundsHoldAParameter) {
  // Rosenbrock with x held at 0.5: the best y is 0.25.
  const auto result = minimize_least_squares(rosenbrock, {0.5, 1.0}, box({0.5, -2}, {0.5, 2}));
  EXPECT_DOUBLE_EQ(result.x[0], 0.5);
  EXPECT_NEAR(result.x[1], 0.25, 1e-6);
}

TEST(BoundedLeastSquares, TheBudgetIsKept) {
  const auto result = minimize_least_squares(rosenbrock, {-1.2, 1.0}, box({-2, -2}, {2, 2}, 7));
  EXPECT_LE(result.evaluations, 7);
  EXPECT_LT(result.cost, 24.2);  // below the start's 4.4^2 + 2.2^2
}

TEST(BoundedLeastSquares, BadSettingsAndAnInfeasibleStartAreErrors) {
  EXPECT_THROW(minimize_least_squares(rosenbrock, {0.0, 0.0}, box({0}, {1})), std::invalid_argument);
  EXPECT_THROW(minimize_least_squares(rosenbrock, {0.0, 0.0}, box({0, 2}, {1, 1})), std::invalid_argument);
  EXPECT_THROW(minimize_least_squares(rosenbrock, {}, box({}, {})), std::invalid_argument);
  const auto never = [](std::span<const double>) -> std::optional<std::vector<double>> { return std::nullopt; };
  EXPECT_THROW(minimize_least_squares(never, {0.0}, box({-1}, {1})), std::runtime_error);
}

}  // namespace
}  // namespace softwrist::optimize
