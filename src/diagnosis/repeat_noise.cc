#include "diagnosis/repeat_noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>

#include <fmt/format.h>

namespace softwrist::diagnosis {
namespace {

// RMS over rows of the commands' difference (all four muscles), over the rows both trials have.
double command_difference(const Trial& a, const Trial& b) {
  const std::size_t n = std::min(a.trajectory.size(), b.trajectory.size());
  double ss = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t m = 0; m < 4; ++m)
      ss += std::pow(a.trajectory[i].command_kpa[m] - b.trajectory[i].command_kpa[m], 2);
  }
  return n == 0 ? INFINITY : std::sqrt(ss / static_cast<double>(n));
}

// RMS over rows of the commands about their mean.
double command_spread(const Trial& a) {
  std::array<double, 4> mean{};
  for (const auto& s : a.trajectory) {
    for (std::size_t m = 0; m < 4; ++m) mean[m] += s.command_kpa[m] / static_cast<double>(a.trajectory.size());
  }
  double ss = 0.0;
  for (const auto& s : a.trajectory) {
    for (std::size_t m = 0; m < 4; ++m) ss += std::pow(s.command_kpa[m] - mean[m], 2);
  }
  return std::sqrt(ss / static_cast<double>(std::max<std::size_t>(1, a.trajectory.size())));
}

bool same_task(const PreparedTrial& a, const PreparedTrial& b) {
  const Trial &ta = *a.trial, &tb = *b.trial;
  if (a.pressures != b.pressures || ta.conventions.placement != tb.conventions.placement ||
      ta.conventions.posture != tb.conventions.posture) {
    return false;
  }
  const double la = ta.trajectory.back().t - ta.trajectory.front().t;
  const double lb = tb.trajectory.back().t - tb.trajectory.front().t;
  if (std::abs(la - lb) > 0.05 * std::max(la, lb)) return false;
  const double spread = std::max(command_spread(ta), command_spread(tb));
  return spread > 0.0 && command_difference(ta, tb) < kRepeatCommandSimilarity * spread;
}

// Points of trajectory trial `p` by (channel, row): prepare_trajectory lays them out channel by channel.
std::size_t rows_of(const PreparedTrial& p) { return p.trial->trajectory.size(); }

struct RepeatSpread {
  double noise2 = 0.0;       // per-sample noise variance
  double block_mean2 = 0.0;  // variance of a 1 s block's mean
  double block_size = 0.0;   // mean samples per block
  int units = 0;             // distinct 4 s units of one trial
};

// Each repetition's nominal residuals less the repetitions' mean, over the rows all of them have: d[k][c * rows + i]
// for member k of the set, channel c, row i.
struct Deviations {
  int channels = 0;
  std::size_t rows = 0;
  std::vector<std::vector<double>> d;
};

Deviations deviations_of(const std::vector<PreparedTrial>& trials, const std::vector<std::vector<double>>& residuals,
                         const std::vector<std::size_t>& set) {
  Deviations dev{.channels = trials[set.front()].pressures ? 4 : 2, .rows = rows_of(trials[set.front()])};
  for (std::size_t t : set) dev.rows = std::min(dev.rows, rows_of(trials[t]));
  const double k = static_cast<double>(set.size());
  dev.d.assign(set.size(), std::vector<double>(static_cast<std::size_t>(dev.channels) * dev.rows));
  for (std::size_t c = 0; c < static_cast<std::size_t>(dev.channels); ++c) {
    for (std::size_t i = 0; i < dev.rows; ++i) {
      double mean = 0.0;
      for (std::size_t t : set) mean += residuals[t][c * rows_of(trials[t]) + i] / k;
      for (std::size_t j = 0; j < set.size(); ++j) {
        dev.d[j][c * dev.rows + i] = residuals[set[j]][c * rows_of(trials[set[j]]) + i] - mean;
      }
    }
  }
  return dev;
}

// [s] The commands' lags that predict a regulator's response: every row up to 50 ms, then every 50 ms up to 2 s, many
// times the nominal QB3's 0.06 s time constant and the seconds of a slow vent or an underdamped second-order response.
constexpr double kCommandLagStep = 0.05, kCommandLagMax = 2.0;

// Pressures only: removes from the deviations what the same muscle's command deviations predict (least squares on
// their values 0-2 s before, one response per muscle for all repetitions), and returns the coefficients fitted.
// Repetitions of a closed-loop task differ in their commands; a regulator that differs from the model answers each
// with its own error, which is the model's, not the monitor's noise (seed 32's second-order regulator: a
// repeat-to-repeat spread of 0.55 kPa where the monitors' noise is 0.15). The monitors read the regulators and feed no
// controller, so their noise is independent of the commands and stays; the angles' noise does not (the controller
// answers the IMUs' wander, so the commands' deviations carry it), and their deviations are left whole.
int remove_command_response(const std::vector<PreparedTrial>& trials, const std::vector<std::size_t>& set,
                            Deviations& dev) {
  const auto& first = trials[set.front()].trial->trajectory;
  if (dev.rows < 2) return 0;
  const double dt = (first[dev.rows - 1].t - first.front().t) / static_cast<double>(dev.rows - 1);
  if (!(dt > 0.0)) return 0;
  // Lag bins [edges[b], edges[b + 1]) rows: one row each over the first step (a regulator's quick response), then a
  // step each; a bin's regressor is the commands' mean over it, so that the response is a kernel constant over each
  // bin (a closed-loop command changes from row to row, and a kernel sampled once per bin would miss that).
  const auto step = static_cast<std::size_t>(std::max(1.0, std::round(kCommandLagStep / dt)));
  const auto last = static_cast<std::size_t>(std::round(kCommandLagMax / dt));
  std::vector<std::size_t> edges;
  for (std::size_t l = 0; l <= last + 1; l += l < step ? 1 : step) edges.push_back(l);
  const std::size_t bins = edges.size() - 1;
  const std::size_t k = set.size(), rows = dev.rows;
  int fitted = 0;
  for (std::size_t m = 0; m < 4; ++m) {
    Eigen::MatrixXd commands(k, rows);
    for (std::size_t j = 0; j < k; ++j) {
      for (std::size_t i = 0; i < rows; ++i) commands(j, i) = trials[set[j]].trial->trajectory[i].command_kpa[m];
    }
    commands.rowwise() -= commands.colwise().mean();
    Eigen::MatrixXd x(k * rows, bins);
    Eigen::VectorXd y(k * rows);
    for (std::size_t j = 0; j < k; ++j) {
      // sum[i]: the deviations of rows before i, the first row's held before the log (the trial's start state)
      std::vector<double> sum(rows + 1, 0.0);
      for (std::size_t i = 0; i < rows; ++i) sum[i + 1] = sum[i] + commands(j, i);
      const auto before = [&](std::ptrdiff_t i) {  // the sum of the rows before row i, i <= 0 counting the first
        return i >= 0 ? sum[static_cast<std::size_t>(i)] : static_cast<double>(i) * commands(j, 0);
      };
      for (std::size_t i = 0; i < rows; ++i) {
        y(j * rows + i) = dev.d[j][m * rows + i];
        for (std::size_t b = 0; b < bins; ++b) {  // rows i - edges[b + 1] + 1 .. i - edges[b]
          const auto hi = static_cast<std::ptrdiff_t>(i + 1) - static_cast<std::ptrdiff_t>(edges[b]);
          const auto lo = static_cast<std::ptrdiff_t>(i + 1) - static_cast<std::ptrdiff_t>(edges[b + 1]);
          x(j * rows + i, b) = (before(hi) - before(lo)) / static_cast<double>(edges[b + 1] - edges[b]);
        }
      }
    }
    if (!(x.squaredNorm() > 0.0)) continue;  // the same commands every time: nothing to predict
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
    const Eigen::VectorXd left = y - x * qr.solve(y);
    for (std::size_t j = 0; j < k; ++j) {
      for (std::size_t i = 0; i < rows; ++i) dev.d[j][m * rows + i] = left(j * rows + i);
    }
    fitted += static_cast<int>(qr.rank());
  }
  return fitted;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  const double upper = v[mid];
  if (v.size() % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
}

// The median of a variance estimate with `dof` degrees of freedom over the variance (normal deviations).
double median_over_variance(double dof) { return boost::math::median(boost::math::chi_squared(dof)) / dof; }

RepeatSpread spread_of(const std::vector<PreparedTrial>& trials, const std::vector<std::vector<double>>& residuals,
                       const std::vector<std::size_t>& set) {
  Deviations dev = deviations_of(trials, residuals, set);
  const bool pressures = trials[set.front()].pressures;
  const int fitted = pressures ? remove_command_response(trials, set, dev) : 0;
  const double k = static_cast<double>(set.size());
  double ss = 0.0;
  std::map<std::pair<std::size_t, int>, std::pair<double, int>> blocks;  // (trial, group) -> sum, n of deviations
  std::map<int, std::pair<double, int>> times;                           // 1 s block -> sum of squares, n of rows
  std::set<int> units;
  for (std::size_t c = 0; c < static_cast<std::size_t>(dev.channels); ++c) {
    for (std::size_t i = 0; i < dev.rows; ++i) {
      for (std::size_t j = 0; j < set.size(); ++j) {
        const std::size_t t = set[j];
        const Point& point = trials[t].points[c * rows_of(trials[t]) + i];
        const double d = dev.d[j][c * dev.rows + i];
        ss += d * d;
        auto& b = blocks[{t, point.group}];
        b.first += d;
        ++b.second;
        auto& time = times[point.group % 1000000];
        time.first += d * d;
        time.second += j == 0 ? 1 : 0;  // rows of every channel
        if (j == 0) units.insert(point.unit);
      }
    }
  }
  RepeatSpread s;
  const double count = static_cast<double>(dev.channels) * static_cast<double>(dev.rows);
  // Deviations from the mean of K repetitions have (K - 1) / K of the noise's variance; the response removed took
  // `fitted` of their (K - 1) count independent parts.
  const double independent = count * (k - 1.0), left = independent - fitted;
  if (count == 0 || blocks.empty() || !(left > 0.0)) return s;
  std::vector<double> mean2;  // of each block: its mean's square, over its variance's share of one repetition's
  double n = 0.0;
  for (const auto& [key, b] : blocks) {
    mean2.push_back(std::pow(b.first / b.second, 2) * k / (k - 1.0));
    n += b.second;
  }
  s.block_size = n / static_cast<double>(blocks.size());
  s.units = static_cast<int>(units.size());
  if (!pressures) {
    s.noise2 = ss / independent;
    s.block_mean2 = std::accumulate(mean2.begin(), mean2.end(), 0.0) / static_cast<double>(mean2.size());
    return s;
  }
  // A monitor's noise is the same all through a trial; what the commands do not predict of a regulator's error is
  // not: a trial that starts while the regulators still move (as closed-loop trials do) differs from its repetitions
  // for the first seconds (seed 32's second-order regulator: 1.4 kPa over the first second, 0.35 after two, 0.16 once
  // the commands' response is removed). So the pressures' noise is the median of its estimates over the 1 s blocks
  // (each pooling every channel and repetition: K - 1 independent deviations of each row), and a block mean's
  // variance the median over the blocks, each over the median of such an estimate of a normal variance. A start
  // that rings for seconds still raises the second (a block's mean is n times as sensitive): conservative.
  std::vector<double> noise2;
  for (const auto& [block, v] : times) {
    const double dof = v.second * (k - 1.0);
    noise2.push_back(v.first / dof / median_over_variance(dof));
  }
  s.noise2 = median(noise2) * independent / left;
  s.block_mean2 = median(mean2) / median_over_variance(1.0) * independent / left;
  return s;
}

}  // namespace

std::vector<std::vector<std::size_t>> repeat_sets(const std::vector<PreparedTrial>& trials) {
  std::vector<std::vector<std::size_t>> sets;
  std::vector<bool> taken(trials.size(), false);
  for (std::size_t a = 0; a < trials.size(); ++a) {
    if (taken[a] || trials[a].trial->kind != TrialKind::kTrajectory || trials[a].trial->trajectory.empty()) continue;
    std::vector<std::size_t> set{a};
    for (std::size_t b = a + 1; b < trials.size(); ++b) {
      if (taken[b] || trials[b].trial->kind != TrialKind::kTrajectory || trials[b].trial->trajectory.empty()) continue;
      if (same_task(trials[a], trials[b])) set.push_back(b);
    }
    if (set.size() < 2) continue;
    for (std::size_t t : set) taken[t] = true;
    sets.push_back(std::move(set));
  }
  return sets;
}

namespace {

// Puts the noise `s` of a repeated task on trial `p` where larger than its own, with its block means' inflation.
void raise_to(PreparedTrial& p, const RepeatSpread& s, int degrees_of_freedom, const std::string& source) {
  const double noise = std::sqrt(s.noise2);
  if (noise > p.noise) {
    p.noise_source = fmt::format("{} (the windowed estimate, {:.3g} {}, misses the noise slower than the motion)",
                                 source, p.noise, p.unit);
    p.noise = noise;
  }
  // A block mean of white noise has noise^2 / n; a sensor's wander leaves far more.
  p.group_inflation = std::max(1.0, s.block_mean2 * s.block_size / (p.noise * p.noise));
  // The deviations' independent pieces: a noise that wanders for seconds makes the blocks of one 4 s unit alike.
  p.noise_dof = std::max(1, degrees_of_freedom);
}

bool same_sensors(const PreparedTrial& a, const PreparedTrial& b) {
  return a.pressures == b.pressures && a.trial->conventions.placement == b.trial->conventions.placement &&
         a.trial->conventions.posture == b.trial->conventions.posture;
}

}  // namespace

void apply_repeat_noise(std::vector<PreparedTrial>& trials, const std::vector<std::vector<std::size_t>>& sets,
                        const std::vector<std::vector<double>>& residuals) {
  std::vector<RepeatSpread> spreads;
  std::vector<bool> repeated(trials.size(), false);
  for (const auto& set : sets) {
    spreads.push_back(spread_of(trials, residuals, set));
    const RepeatSpread& s = spreads.back();
    for (std::size_t t : set) repeated[t] = true;
    if (!(s.noise2 > 0.0)) continue;
    for (std::size_t t : set) {
      raise_to(trials[t], s, (static_cast<int>(set.size()) - 1) * std::max(1, s.units),
               fmt::format("spread of the nominal residuals across {} repetitions of the task", set.size()));
    }
  }
  // A trajectory without repetitions of its own, read by sensors that were (the same rig, posture and kind of
  // signal): their wander is the sensors', not the task's, so it takes the least noise its sensors showed in a
  // repeated task. On the independent device, a closed-loop trial whose commands drifted from its task's repetitions
  // was otherwise weighed with its windowed 0.038 deg against the repetitions' 0.55 deg, and its 4 deg of model
  // error read as 116 noise units, outweighing every other trial.
  for (std::size_t t = 0; t < trials.size(); ++t) {
    if (repeated[t] || trials[t].trial->kind != TrialKind::kTrajectory) continue;
    std::size_t quietest = sets.size();
    for (std::size_t k = 0; k < sets.size(); ++k) {
      if (!(spreads[k].noise2 > 0.0) || !same_sensors(trials[t], trials[sets[k].front()])) continue;
      if (quietest == sets.size() || spreads[k].noise2 < spreads[quietest].noise2) quietest = k;
    }
    if (quietest == sets.size()) continue;
    const auto& set = sets[quietest];
    raise_to(trials[t], spreads[quietest], (static_cast<int>(set.size()) - 1) * std::max(1, spreads[quietest].units),
             fmt::format("spread of the nominal residuals across {} repetitions of {} on the same sensors", set.size(),
                         trials[set.front()].name));
  }
}

}  // namespace softwrist::diagnosis
