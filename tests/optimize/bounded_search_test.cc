// The one bounded local search (optimize/bounded_search.h) and its policy for how a search ends.

#include "optimize/bounded_search.h"

#include <cmath>
#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softwrist::optimize {
namespace {

using ::testing::HasSubstr;

double bowl(std::span<const double> x) { return std::pow(x[0] - 0.3, 2) + 2.0 * std::pow(x[1] + 0.2, 2); }

TEST(BoundedSearch, EveryAlgorithmFindsTheMinimumInsideTheBounds) {
  for (const LocalAlgorithm algorithm :
       {LocalAlgorithm::kNelderMead, LocalAlgorithm::kSubplex, LocalAlgorithm::kBobyqa}) {
    const BoundedSearchResult r = minimize_bounded(bowl, {0.9, 0.9},
                                                   {.algorithm = algorithm,
                                                    .lower = {-1.0, -1.0},
                                                    .upper = {1.0, 1.0},
                                                    .x_tolerance_abs = 1e-8,
                                                    .max_evaluations = 2000});
    EXPECT_NEAR(r.x[0], 0.3, 1e-4);
    EXPECT_NEAR(r.x[1], -0.2, 1e-4);
    EXPECT_NEAR(r.value, bowl(r.x), 0.0) << "the value is the objective at the point returned";
    EXPECT_GT(r.evaluations, 0);
    EXPECT_TRUE(r.stopped_by.empty()) << r.stopped_by;
  }
}

TEST(BoundedSearch, AMinimumOutsideTheBoundsEndsOnTheBoundAndTheStartIsClamped) {
  int outside = 0;
  const auto objective = [&](std::span<const double> x) {
    outside += (x[0] < 0.5 || x[0] > 2.0) ? 1 : 0;
    return std::pow(x[0] - 3.0, 2);
  };
  const BoundedSearchResult r = minimize_bounded(
      objective, {-5.0}, {.lower = {0.5}, .upper = {2.0}, .x_tolerance_abs = 1e-9, .max_evaluations = 500});
  EXPECT_NEAR(r.x[0], 2.0, 1e-6);
  EXPECT_EQ(outside, 0) << "never evaluated outside the bounds, the start included";
}

TEST(BoundedSearch, TheBudgetIsKeptAndTheBestPointSoFarReturned) {
  const BoundedSearchResult r =
      minimize_bounded(bowl, {0.9, 0.9}, {.lower = {-1.0, -1.0}, .upper = {1.0, 1.0}, .max_evaluations = 7});
  EXPECT_LE(r.evaluations, 7);
  EXPECT_LE(r.value, bowl(std::vector<double>{0.9, 0.9}));
}

TEST(BoundedSearch, AnObjectivesExceptionReachesTheCallerUnchanged) {
  int calls = 0;
  const auto objective = [&](std::span<const double> x) -> double {
    if (++calls == 5) throw std::domain_error("replay diverged");
    return bowl(x);
  };
  EXPECT_THAT(
      [&] {
        minimize_bounded(objective, {0.9, 0.9}, {.lower = {-1.0, -1.0}, .upper = {1.0, 1.0}});
      },
      ::testing::ThrowsMessage<std::domain_error>(HasSubstr("replay diverged")));
  EXPECT_EQ(calls, 5) << "the search stopped at the exception";
}

TEST(BoundedSearch, InvalidSettingsAreRefusedBeforeAnyEvaluation) {
  int calls = 0;
  const auto objective = [&](std::span<const double> x) {
    ++calls;
    return bowl(x);
  };
  EXPECT_THROW(minimize_bounded(objective, {0.0, 0.0}, {.lower = {-1.0}, .upper = {1.0, 1.0}}), std::invalid_argument);
  EXPECT_THROW(minimize_bounded(objective, {0.0, 0.0}, {.lower = {1.0, -1.0}, .upper = {-1.0, 1.0}}),
               std::invalid_argument);
  EXPECT_THROW(minimize_bounded(objective, {}, {}), std::invalid_argument);
  EXPECT_THROW(
      minimize_bounded(objective, {0.0, 0.0}, {.lower = {-1.0, -1.0}, .upper = {1.0, 1.0}, .max_evaluations = 0}),
      std::invalid_argument);
  EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace softwrist::optimize
