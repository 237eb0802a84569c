#include "diagnosis/repeat_noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>

#include <Eigen/Dense>

#include <fmt/format.h>

#include "diagnosis/localization.h"

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

// Each repetition's nominal residuals less the repetitions' mean, over the rows all of them have: d[j][c * rows + i]
// for the set's j-th trial, channel c, row i. Empty where a residual is not finite.
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
      if (!std::isfinite(mean)) return {};
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

// Lag bins [edges[b], edges[b + 1]) in rows of `dt`: one row each over the first step (a regulator's quick
// response), then a step each, the last ending at kCommandLagMax.
std::vector<std::size_t> lag_bin_edges(double dt) {
  const auto step = static_cast<std::size_t>(std::max(1.0, std::round(kCommandLagStep / dt)));
  const auto end = static_cast<std::size_t>(std::round(kCommandLagMax / dt)) + 1;
  std::vector<std::size_t> edges;
  for (std::size_t l = 0; l < end; l += l < step ? 1 : step) edges.push_back(l);
  edges.push_back(end);
  return edges;
}

// Row i, bin b: the mean of `deviation` (one repetition's command deviations) over the rows i - edges[b + 1] + 1 ..
// i - edges[b], the rows before the log at `before` (the regulators' command then, as the replay holds it). The mean
// over a bin, not one row of it, so that the response is a kernel constant over each bin: a closed-loop command
// changes from row to row, and a kernel sampled once per bin would miss that.
Eigen::MatrixXd lagged_command_means(const Eigen::RowVectorXd& deviation, double before,
                                     const std::vector<std::size_t>& edges) {
  const auto rows = static_cast<std::size_t>(deviation.size());
  std::vector<double> sum(rows + 1, 0.0);  // sum[i]: of the rows before row i
  for (std::size_t i = 0; i < rows; ++i) sum[i + 1] = sum[i] + deviation(static_cast<Eigen::Index>(i));
  const auto sum_before = [&](std::ptrdiff_t i) {
    return i >= 0 ? sum[static_cast<std::size_t>(i)] : static_cast<double>(i) * before;
  };
  Eigen::MatrixXd x(rows, edges.size() - 1);
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
      const auto hi = static_cast<std::ptrdiff_t>(i + 1) - static_cast<std::ptrdiff_t>(edges[b]);
      const auto lo = static_cast<std::ptrdiff_t>(i + 1) - static_cast<std::ptrdiff_t>(edges[b + 1]);
      x(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(b)) =
          (sum_before(hi) - sum_before(lo)) / static_cast<double>(edges[b + 1] - edges[b]);
    }
  }
  return x;
}

// Pressures only: removes from the deviations what the same muscle's command deviations predict (least squares on
// their means over lag bins 0-2 s back, one response per muscle for all repetitions), and returns the rank of that
// fit. Repetitions of a closed-loop task differ in their commands; a regulator that differs from the model answers
// each with its own error, which is the model's, not the monitor's noise (seed 32's second-order regulator: a
// repeat-to-repeat spread of 0.55 kPa where the monitors' noise is 0.15). The monitors read the regulators and feed no
// controller, so their noise is independent of the commands and stays (a regulator's own pressure fluctuation, which
// moves the wrist and so the commands that follow, would lose a little of its slow part); the angles' noise is not
// (the controller answers the IMUs' wander, so the commands' deviations carry it), and their deviations stay whole.
int remove_command_response(const std::vector<PreparedTrial>& trials, const std::vector<std::size_t>& set,
                            Deviations& dev) {
  const auto& first = trials[set.front()].trial->trajectory;
  if (dev.rows < 2) return 0;
  const double dt = (first[dev.rows - 1].t - first.front().t) / static_cast<double>(dev.rows - 1);
  if (!(dt > 0.0)) return 0;
  const std::vector<std::size_t> edges = lag_bin_edges(dt);
  const std::size_t k = set.size(), rows = dev.rows, bins = edges.size() - 1;
  int rank = 0;
  for (std::size_t m = 0; m < 4; ++m) {
    Eigen::MatrixXd commands(k, rows);
    for (std::size_t j = 0; j < k; ++j) {
      for (std::size_t i = 0; i < rows; ++i) commands(j, i) = trials[set[j]].trial->trajectory[i].command_kpa[m];
    }
    commands.rowwise() -= commands.colwise().mean();
    Eigen::MatrixXd x(k * rows, bins);
    Eigen::VectorXd y(k * rows);
    for (std::size_t j = 0; j < k; ++j) {
      // The replay holds the first command before the log where the angles were zeroed at the start, else the
      // regulators start vented (replay.cc), alike in every repetition.
      const double before = trials[set[j]].trial->conventions.angles_zeroed_at_start ? commands(j, 0) : 0.0;
      x.middleRows(static_cast<Eigen::Index>(j * rows), static_cast<Eigen::Index>(rows)) =
          lagged_command_means(commands.row(static_cast<Eigen::Index>(j)), before, edges);
      for (std::size_t i = 0; i < rows; ++i) y(j * rows + i) = dev.d[j][m * rows + i];
    }
    if (!(x.squaredNorm() > 0.0)) continue;  // the same commands every time: nothing to predict
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
    const Eigen::VectorXd unpredicted = y - x * qr.solve(y);
    for (std::size_t j = 0; j < k; ++j) {
      for (std::size_t i = 0; i < rows; ++i) dev.d[j][m * rows + i] = unpredicted(j * rows + i);
    }
    rank += static_cast<int>(qr.rank());
  }
  return rank;
}

double median_of(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The mean of the values at most `cutoff`.
double mean_up_to(const std::vector<double>& v, double cutoff) {
  double sum = 0.0;
  int n = 0;
  for (double x : v) {
    if (x <= cutoff) {
      sum += x;
      ++n;
    }
  }
  return n == 0 ? 0.0 : sum / n;
}

// The pressures' 1 s blocks left out of their noise: a block whose variance lies more than three robust standard
// deviations (1.4826 times the median absolute deviation) above the median block's. The blocks' own scatter sets the
// bound, so a noise correlated within a block, which scatters the blocks' variances more than white noise does, keeps
// its blocks (8 independent parts per block: 1.8 % left out, the variance 3 % low; a simulation of 2 million).
double noise_without_outlying_blocks(const std::vector<double>& block_variances) {
  if (block_variances.empty()) return 0.0;
  const double median = median_of(block_variances);
  std::vector<double> deviation;
  for (double v : block_variances) deviation.push_back(std::abs(v - median));
  return mean_up_to(block_variances, median + 3.0 * 1.4826 * median_of(deviation));
}

// A block mean whose square is 24 times the median's is left out of the block means' variance: chi-squared with one
// degree of freedom exceeds that once in 1000.
constexpr double kBlockMeanOutlier = 24.0;

// Sums over the deviations: per (trial, 1 s group) their sum and number, per 1 s of the log (the set's first trial's)
// the sum of squares and number of rows, and the distinct 4 s units of the first trial.
struct BlockSums {
  double ss = 0.0;
  std::map<std::pair<std::size_t, int>, std::pair<double, int>> blocks;
  std::map<int, std::pair<double, int>> seconds;
  std::set<int> units;
};

BlockSums block_sums(const std::vector<PreparedTrial>& trials, const std::vector<std::size_t>& set,
                     const Deviations& dev) {
  BlockSums sums;
  for (std::size_t c = 0; c < static_cast<std::size_t>(dev.channels); ++c) {
    for (std::size_t i = 0; i < dev.rows; ++i) {
      const Point& first = trials[set.front()].points[c * rows_of(trials[set.front()]) + i];
      auto& second = sums.seconds[first.group % 1000000];
      ++second.second;
      sums.units.insert(first.unit);
      for (std::size_t j = 0; j < set.size(); ++j) {
        const std::size_t t = set[j];
        const double d = dev.d[j][c * dev.rows + i];
        sums.ss += d * d;
        second.first += d * d;
        auto& b = sums.blocks[{t, trials[t].points[c * rows_of(trials[t]) + i].group}];
        b.first += d;
        ++b.second;
      }
    }
  }
  return sums;
}

RepeatSpread spread_of(const std::vector<PreparedTrial>& trials, const std::vector<std::vector<double>>& residuals,
                       const std::vector<std::size_t>& set) {
  Deviations dev = deviations_of(trials, residuals, set);
  if (dev.d.empty()) return {};
  const bool pressures = trials[set.front()].pressures;
  const int rank = pressures ? remove_command_response(trials, set, dev) : 0;
  const BlockSums sums = block_sums(trials, set, dev);
  const double k = static_cast<double>(set.size());
  // Deviations from the mean of K repetitions have (K - 1) / K of the noise's variance: (K - 1) rows' worth of
  // independent parts per row, less the rank of the response removed.
  const double independent = static_cast<double>(dev.channels) * static_cast<double>(dev.rows) * (k - 1.0);
  const double dof = independent - rank;
  if (sums.blocks.empty() || !(dof > 0.0)) return {};
  RepeatSpread s;
  std::vector<double> mean2;  // each block's mean squared, over the share (K - 1) / K of one repetition's variance
  double n = 0.0;
  for (const auto& [key, b] : sums.blocks) {
    mean2.push_back(std::pow(b.first / b.second, 2) * k / (k - 1.0));
    n += b.second;
  }
  s.block_size = n / static_cast<double>(sums.blocks.size());
  s.units = static_cast<int>(sums.units.size());
  if (!pressures) {
    s.noise2 = sums.ss / independent;
    s.block_mean2 = std::accumulate(mean2.begin(), mean2.end(), 0.0) / static_cast<double>(mean2.size());
    return s;
  }
  // A monitor's noise is the same all through a trial; what the commands do not predict of a regulator's error is
  // not: a trial that starts while the regulators still move (as closed-loop trials do) differs from its repetitions
  // for its first seconds (seed 32's second-order regulator: 1.4 kPa over the first second, 0.35 after two, 0.16 once
  // the commands' response is removed). So the pressures' noise is the mean over the 1 s blocks of the log but those
  // far above the others (their median alone would read a correlated noise low), and likewise the variance of a
  // block's mean. A start that rings for seconds still raises both a little (a block's mean is n times as sensitive).
  std::vector<double> noise2;
  for (const auto& [second, v] : sums.seconds) noise2.push_back(v.first / (v.second * (k - 1.0)));
  s.noise2 = noise_without_outlying_blocks(noise2) * independent / dof;
  s.block_mean2 = mean2.empty() ? 0.0 : mean_up_to(mean2, kBlockMeanOutlier * median_of(mean2)) * independent / dof;
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
  // Measured on the independent device (the nominal and latency_jitter data sets of seeds 38, 40 and 41, a throwaway
  // print): the angles' 1 s block means of the deviations correlate 0.42-0.81 from one second to the next and
  // 0.08-0.60 two apart; an AR(1) at 0.77 leaves a 12 s trial's 12 blocks the information of 3.1, what its three units
  // count. The pressures' correlate -0.17 to 0.16, so their count is conservative there (12 nearly independent blocks
  // counted as 3); left so: within the tolerances their excess was at most 0.61 noise units on the nominal,
  // latency_jitter, glove_slide, strap_stiffening and direction_dependent data sets of seeds 38-40, below min_gap
  // whatever the test's power.
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
      trials[t].repeat_set = static_cast<int>(spreads.size() - 1);
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

RepeatMeanTest repeat_mean_test(const std::vector<PreparedTrial>& trials,
                                const std::vector<std::vector<double>>& residuals,
                                const std::vector<std::size_t>& set) {
  RepeatMeanTest out;
  if (set.size() < 2) return out;
  const PreparedTrial& first = trials[set.front()];
  const std::size_t channels = first.pressures ? 4 : 2;
  const double k = static_cast<double>(set.size());
  std::size_t rows = rows_of(first);
  double noise2 = 0.0, block2 = 0.0;  // the members' mean noise variance, and n x a group mean's variance
  int dof = std::numeric_limits<int>::max();
  for (std::size_t t : set) {
    if (residuals[t].size() < channels * rows_of(trials[t]) || trials[t].points.size() < channels * rows_of(trials[t]))
      return out;
    rows = std::min(rows, rows_of(trials[t]));
    noise2 += trials[t].noise * trials[t].noise / k;
    block2 += trials[t].noise * trials[t].noise * trials[t].group_inflation / k;
    dof = std::min(dof, trials[t].noise_dof);
  }
  if (!(noise2 > 0.0) || rows == 0) return out;
  // The mean on the first repetition's points, weighed by the group test as a trial whose n x group-mean variance is
  // the members' over K.
  std::vector<double> mean(first.points.size(), 0.0);
  std::vector<std::size_t> rows_tested;
  double ss = 0.0;
  for (std::size_t c = 0; c < channels; ++c) {
    for (std::size_t i = 0; i < rows; ++i) {
      double& m = mean[c * rows_of(first) + i];
      for (std::size_t t : set) m += residuals[t][c * rows_of(trials[t]) + i] / k;
      if (!std::isfinite(m)) return out;
      ss += m * m;
      rows_tested.push_back(c * rows_of(first) + i);
    }
  }
  PreparedTrial of_mean = first;
  of_mean.noise = std::sqrt(noise2 / k);
  of_mean.group_inflation = block2 / noise2;
  of_mean.noise_dof = dof;
  out.p_value = group_test(of_mean, mean, rows_tested).p_value;
  out.excess = std::sqrt(std::max(0.0, ss / static_cast<double>(rows_tested.size()) / noise2 - 1.0 / k));
  return out;
}

}  // namespace softwrist::diagnosis
