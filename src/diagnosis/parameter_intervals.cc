#include "diagnosis/parameter_intervals.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "diagnosis/gap_problem.h"
#include "diagnosis/joint_refit.h"
#include "diagnosis/setting_scatter.h"
#include "sim/device.h"

namespace softwrist::diagnosis {
namespace {

// One fitted parameter: which effect of the combination, which of its values.
struct Slot {
  std::size_t effect = 0, index = 0;
  const ParameterSpec* spec = nullptr;
};

// Every measurement's residual in units of its trial's noise; `rho` gets the largest lag-1 autocorrelation of a
// trial's residuals.
std::vector<double> weighted_residuals(const std::vector<PreparedTrial>& prepared, const Predictions& predictions,
                                       double* rho) {
  std::vector<double> out;
  if (rho) *rho = 0.0;
  for (std::size_t t = 0; t < prepared.size(); ++t) {
    const std::vector<double> r = whitened(prepared[t], residuals_of(prepared[t], predictions[t]));
    const double noise = prepared[t].noise > 0.0 ? prepared[t].noise : 1.0;
    double lag0 = 0.0, lag1 = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      out.push_back(r[i] / noise);
      lag0 += r[i] * r[i];
      if (i > 0) lag1 += r[i] * r[i - 1];
    }
    if (rho && lag0 > 0.0 && r.size() > 10) *rho = std::max(*rho, lag1 / lag0);
  }
  return out;
}

// The diagonal of the pseudo-inverse of J^T J: a flat direction (a parameter the data do not see) gets an unbounded
// variance.
std::vector<double> unit_variances(const Eigen::MatrixXd& jacobian) {
  const Eigen::Index p = jacobian.cols();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(jacobian.transpose() * jacobian);
  const double largest = eigen.eigenvalues().maxCoeff();
  Eigen::VectorXd inverse_values = eigen.eigenvalues();
  for (Eigen::Index i = 0; i < p; ++i) {
    inverse_values(i) = inverse_values(i) > 1e-12 * largest && inverse_values(i) > 0.0
                            ? 1.0 / inverse_values(i)
                            : std::numeric_limits<double>::infinity();
  }
  std::vector<double> out(static_cast<std::size_t>(p), 0.0);
  for (Eigen::Index k = 0; k < p; ++k) {
    for (Eigen::Index i = 0; i < p; ++i) {
      const double v = eigen.eigenvectors()(k, i);
      if (v * v > 1e-12) out[static_cast<std::size_t>(k)] += v * v * inverse_values(i);
    }
  }
  return out;
}

}  // namespace

std::vector<ParameterInterval> combination_intervals(const Diagnosis& d, const sim::DeviceDescription& nominal,
                                                     ReplayEngine& engine) {
  if (d.combination.empty()) return {};
  // The nominal with the rigs its trials name, as the diagnosis prepared it (their placement files, routed as the
  // diagnosis chose).
  ModelVariant base{.device = nominal};
  if (d.corrected) {
    for (const auto& [placement, rig] : d.corrected->rigs) base.rigs.emplace(placement, sim::load_device(placement));
  }
  base.route(d.routing);
  std::vector<PreparedTrial> prepared = d.prepared;
  const GapProblem problem(prepared, engine);
  std::vector<std::vector<double>> values;
  std::vector<Slot> slots;
  for (std::size_t e = 0; e < d.combination.size(); ++e) {
    values.push_back(d.combination[e].values);
    const EffectSpec& spec = effect_spec(d.combination[e].id);
    for (std::size_t i = 0; i < spec.parameters.size(); ++i) slots.push_back({e, i, &spec.parameters[i]});
  }
  double rho = 0.0;
  const std::vector<double> r0 =
      weighted_residuals(prepared, problem.evaluate(combined_variant(d.combination, values, base), false), &rho);
  const auto n = static_cast<Eigen::Index>(r0.size());
  const auto p = static_cast<Eigen::Index>(slots.size());
  // The Jacobian in the searched (unit) space, by central differences (one-sided at a bound).
  constexpr double kStep = 0.002;
  Eigen::MatrixXd jacobian(n, p);
  std::vector<double> u0(slots.size());
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const Slot& s = slots[k];
    u0[k] = s.spec->to_unit(values[s.effect][s.index]);
    const double up = std::min(1.0, u0[k] + kStep), down = std::max(0.0, u0[k] - kStep);
    // A side the model cannot be built or replayed at (an unphysical corner of the range) is replaced by the fit
    // itself: a one-sided difference.
    std::vector<double> sides[2];
    double at[2] = {up, down};
    for (int side = 0; side < 2; ++side) {
      std::vector<std::vector<double>> moved = values;
      moved[s.effect][s.index] = s.spec->from_unit(at[side]);
      try {
        sides[side] = weighted_residuals(
            prepared, problem.evaluate(combined_variant(d.combination, moved, base), false), nullptr);
      } catch (const std::exception&) {
        sides[side] = r0;
        at[side] = u0[k];
      }
    }
    const double width = at[0] - at[1];
    for (Eigen::Index i = 0; i < n; ++i) {
      jacobian(i, static_cast<Eigen::Index>(k)) =
          width > 0.0 ? (sides[0][static_cast<std::size_t>(i)] - sides[1][static_cast<std::size_t>(i)]) / width : 0.0;
    }
  }
  double sum_squares = 0.0;
  for (double r : r0) sum_squares += r * r;
  const double s2 = sum_squares / static_cast<double>(std::max<Eigen::Index>(1, n - p));
  rho = std::clamp(rho, 0.0, 0.999);
  const double correlation = (1.0 + rho) / (1.0 - rho);
  const std::vector<double> variances = unit_variances(jacobian);
  std::vector<ParameterInterval> out;
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const double half = 1.959964 * std::sqrt(variances[k] * s2 * correlation);
    const Slot& s = slots[k];
    const double low_u = std::isfinite(half) ? std::max(0.0, u0[k] - half) : 0.0;
    const double high_u = std::isfinite(half) ? std::min(1.0, u0[k] + half) : 1.0;
    out.push_back({.effect = d.combination[s.effect].name,
                   .name = s.spec->name,
                   .value = values[s.effect][s.index],
                   .low = s.spec->from_unit(low_u),
                   .high = s.spec->from_unit(high_u),
                   .relative_width = high_u - low_u});
  }
  return out;
}

}  // namespace softwrist::diagnosis
