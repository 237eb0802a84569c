#include "optimize/bounded_least_squares.h"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>

namespace softwrist::optimize {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void check_settings(const std::vector<double>& start, const LeastSquaresSettings& s) {
  const std::size_t n = start.size();
  if (n == 0) throw std::invalid_argument("least squares: no parameters");
  if (s.lower.size() != n || s.upper.size() != n) {
    throw std::invalid_argument("least squares: bounds must have one entry per parameter");
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!(s.lower[k] <= s.upper[k])) {
      throw std::invalid_argument("least squares: lower bound " + std::to_string(k) + " is above its upper");
    }
  }
  if (!s.cheap.empty() && s.cheap.size() != n) throw std::invalid_argument("least squares: cheap must have n entries");
  if (!(s.difference_step > 0.0 && s.difference_step < 0.5)) {
    throw std::invalid_argument("least squares: difference_step must lie in (0, 0.5)");
  }
  if (s.max_evaluations < 1 || s.jobs < 1) throw std::invalid_argument("least squares: budget and jobs must be >= 1");
}

VectorXd to_vector(const std::vector<double>& v) { return Eigen::Map<const VectorXd>(v.data(), std::ssize(v)); }

// The damped Gauss-Newton step d from x, with parameters that would leave [lower, upper] held at the bound.
VectorXd damped_step(const MatrixXd& H, const VectorXd& g, double lambda, const VectorXd& x, const VectorXd& lower,
                     const VectorXd& upper) {
  const Eigen::Index n = x.size();
  const double floor = 1e-6 * std::max(H.diagonal().maxCoeff(), 0.0) + 1e-12;
  std::vector<bool> fixed(static_cast<std::size_t>(n), false);
  VectorXd d = VectorXd::Zero(n);
  for (Eigen::Index pass = 0; pass <= n; ++pass) {
    std::vector<Eigen::Index> free;
    for (Eigen::Index k = 0; k < n; ++k) {
      if (!fixed[static_cast<std::size_t>(k)]) free.push_back(k);
    }
    if (free.empty()) break;
    const Eigen::Index m = std::ssize(free);
    MatrixXd A(m, m);
    VectorXd b(m);
    for (Eigen::Index i = 0; i < m; ++i) {
      b[i] = -g[free[i]];
      for (Eigen::Index k = 0; k < n; ++k) {
        if (fixed[static_cast<std::size_t>(k)]) b[i] -= H(free[i], k) * d[k];
      }
      for (Eigen::Index j = 0; j < m; ++j) A(i, j) = H(free[i], free[j]);
      A(i, i) += lambda * (H(free[i], free[i]) + floor);
    }
    const VectorXd df = A.ldlt().solve(b);
    bool violated = false;
    for (Eigen::Index i = 0; i < m; ++i) {
      const Eigen::Index k = free[i];
      d[k] = df[i];
      if (x[k] + d[k] > upper[k] || x[k] + d[k] < lower[k]) {
        d[k] = std::clamp(x[k] + d[k], lower[k], upper[k]) - x[k];
        fixed[static_cast<std::size_t>(k)] = violated = true;
      }
    }
    if (!violated) break;
  }
  return d;
}

class Solver {
 public:
  Solver(const ResidualFunction& f, const LeastSquaresSettings& s) : f_(f), s_(s) {}

  std::optional<VectorXd> evaluate(const VectorXd& x) { return evaluate(f_, x); }

  // The Jacobian at x, where the residuals are `r`: differenced on difference_residuals where they are set and
  // feasible at x, each column where a point it differences is infeasible there differenced again on the residuals
  // themselves (an infeasible direction is theirs to tell), budget permitting (otherwise it stays fenced).
  MatrixXd jacobian(const VectorXd& x, const VectorXd& r, VectorXd& lower, VectorXd& upper) {
    const Eigen::Index n = x.size();
    MatrixXd J = MatrixXd::Zero(r.size(), n);
    lower = to_vector(s_.lower);
    upper = to_vector(s_.upper);
    std::vector<Eigen::Index> columns(static_cast<std::size_t>(n));
    std::iota(columns.begin(), columns.end(), Eigen::Index{0});
    if (!s_.difference_residuals) {
      differences(f_, x, r, columns, J, lower, upper);
      return J;
    }
    if (auto base = evaluate(s_.difference_residuals, x); base && base->size() == r.size()) {
      columns = differences(s_.difference_residuals, x, *base, columns, J, lower, upper);
      if (columns.empty() || evaluations_ + 2 * std::ssize(columns) >= s_.max_evaluations) return J;
      for (const Eigen::Index k : columns) {
        lower[k] = s_.lower[static_cast<std::size_t>(k)];
        upper[k] = s_.upper[static_cast<std::size_t>(k)];
      }
    }
    differences(f_, x, r, columns, J, lower, upper);
    return J;
  }

  int evaluations() const { return evaluations_; }

 private:
  // Forward differences of `f` (`r` at x) for `columns` of J, stepping inwards at an upper bound and the other way
  // where a step is infeasible. A direction found infeasible is fenced: the next step holds that parameter where it
  // is (`lower`, `upper` narrowed). Returns the columns where some point was infeasible.
  std::vector<Eigen::Index> differences(const ResidualFunction& f, const VectorXd& x, const VectorXd& r,
                                        const std::vector<Eigen::Index>& columns, MatrixXd& J, VectorXd& lower,
                                        VectorXd& upper) {
    std::vector<char> fenced(static_cast<std::size_t>(x.size()), 0);  // char: written from several threads
    const auto column = [&](Eigen::Index k) {
      const double h = s_.difference_step * (s_.upper[k] - s_.lower[k]);
      for (double sign : {x[k] + h <= s_.upper[k] ? 1.0 : -1.0, x[k] + h <= s_.upper[k] ? -1.0 : 1.0}) {
        VectorXd xk = x;
        xk[k] = std::clamp(x[k] + sign * h, s_.lower[k], s_.upper[k]);
        if (xk[k] == x[k]) continue;
        const auto rk = evaluate(f, xk);
        if (!rk || rk->size() != r.size()) {
          (sign > 0.0 ? upper : lower)[k] = x[k];
          fenced[static_cast<std::size_t>(k)] = 1;
          continue;
        }
        J.col(k) = (*rk - r) / (xk[k] - x[k]);
        return;
      }
    };
    std::vector<Eigen::Index> expensive;
    for (const Eigen::Index k : columns) {
      if (!s_.cheap.empty() && s_.cheap[k]) {
        column(k);
      } else {
        expensive.push_back(k);
      }
    }
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto work = [&] {
      for (std::size_t i = next++; i < expensive.size(); i = next++) {
        try {
          column(expensive[i]);
        } catch (...) {
          const std::lock_guard lock(failure_mutex);
          if (!failure) failure = std::current_exception();
        }
      }
    };
    std::vector<std::thread> threads;
    for (int j = 1; j < std::min<int>(s_.jobs, static_cast<int>(expensive.size())); ++j) threads.emplace_back(work);
    work();
    for (auto& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
    std::vector<Eigen::Index> infeasible;
    for (const Eigen::Index k : columns) {
      if (fenced[static_cast<std::size_t>(k)]) infeasible.push_back(k);
    }
    return infeasible;
  }

  std::optional<VectorXd> evaluate(const ResidualFunction& f, const VectorXd& x) {
    ++evaluations_;
    const auto r = f(std::span<const double>(x.data(), static_cast<std::size_t>(x.size())));
    if (!r) return std::nullopt;
    VectorXd v = to_vector(*r);
    if (!v.allFinite()) return std::nullopt;
    return v;
  }

  const ResidualFunction& f_;
  const LeastSquaresSettings& s_;
  std::atomic<int> evaluations_{0};
};

}  // namespace

LeastSquaresResult minimize_least_squares(const ResidualFunction& residuals, std::vector<double> start,
                                          const LeastSquaresSettings& settings) {
  check_settings(start, settings);
  Solver solver(residuals, settings);
  const Eigen::Index n = std::ssize(start);
  VectorXd x(n);
  for (Eigen::Index k = 0; k < n; ++k) x[k] = std::clamp(start[k], settings.lower[k], settings.upper[k]);
  const auto r0 = solver.evaluate(x);
  if (!r0) throw std::runtime_error("least squares: the start is infeasible");
  VectorXd r = *r0;
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  int iterations = 0;
  MatrixXd jacobian;
  VectorXd lower, upper;
  bool need_jacobian = true;
  bool fresh = false;  // the Jacobian is the finite differences' at x, not yet moved by a secant update
  while (true) {
    if (need_jacobian) {
      // A Jacobian (n evaluations, one more for the base point of difference_residuals) and at least one step.
      const int jacobian_cost = static_cast<int>(n) + (settings.difference_residuals ? 1 : 0);
      if (solver.evaluations() + jacobian_cost + 1 > settings.max_evaluations) break;
      jacobian = solver.jacobian(x, r, lower, upper);
      ++iterations;
      fresh = true;
      need_jacobian = false;
    }
    if (solver.evaluations() >= settings.max_evaluations || lambda >= 1e8) break;
    VectorXd d = damped_step(jacobian.transpose() * jacobian, jacobian.transpose() * r, lambda, x, lower, upper);
    if (d.lpNorm<Eigen::Infinity>() < 1e-12) {
      if (fresh) break;  // no step left on the true local model
      need_jacobian = true;
      continue;
    }
    // A secant model that promises less than the tolerance has stalled: differenced again rather than tried.
    if (!fresh && cost - (r + jacobian * d).squaredNorm() < settings.cost_tolerance_rel * cost) {
      need_jacobian = true;
      continue;
    }
    // An infeasible trial point is backed off along the step (halved up to three times); a worse one raises the
    // damping.
    std::optional<VectorXd> rn;
    for (int halving = 0; halving < 4 && solver.evaluations() < settings.max_evaluations; ++halving, d *= 0.5) {
      rn = solver.evaluate(x + d);
      if (rn) break;
    }
    if (rn && rn->size() == r.size() && rn->squaredNorm() < cost) {
      const double decrease = (cost - rn->squaredNorm()) / cost;
      const bool stepped_on_fresh = fresh;
      if (settings.secant_updates) {
        // Broyden's rank-one update (Broyden 1965): the model now maps the step taken to the change it caused.
        jacobian += ((*rn - r) - jacobian * d) * d.transpose() / d.squaredNorm();
        fresh = false;
      }
      x += d;
      r = *rn;
      cost = r.squaredNorm();
      lambda = std::max(lambda / 5.0, 1e-9);
      // Too little to go on: the fit stops where the differenced model gave the step, and a secant model that gave
      // it is differenced again first.
      if (decrease < settings.cost_tolerance_rel && stepped_on_fresh) break;
      need_jacobian = !settings.secant_updates || decrease < settings.cost_tolerance_rel;
      continue;
    }
    lambda *= 5.0;
    // A secant model that promised a decrease it did not give may be stale: differenced again before damping more.
    if (!fresh) need_jacobian = true;
  }
  return {.x = std::vector<double>(x.data(), x.data() + n),
          .cost = cost,
          .evaluations = solver.evaluations(),
          .iterations = iterations};
}

}  // namespace softwrist::optimize
