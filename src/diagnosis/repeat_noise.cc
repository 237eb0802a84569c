#include "diagnosis/repeat_noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

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

RepeatSpread spread_of(const std::vector<PreparedTrial>& trials, const std::vector<std::vector<double>>& residuals,
                       const std::vector<std::size_t>& set) {
  const PreparedTrial& first = trials[set.front()];
  const int channels = first.pressures ? 4 : 2;
  std::size_t rows = rows_of(first);
  for (std::size_t t : set) rows = std::min(rows, rows_of(trials[t]));
  const double k = static_cast<double>(set.size());
  double ss = 0.0;
  long count = 0;
  std::map<std::pair<std::size_t, int>, std::pair<double, int>> blocks;  // (trial, group) -> sum, n of deviations
  std::set<int> units;
  for (int c = 0; c < channels; ++c) {
    for (std::size_t i = 0; i < rows; ++i) {
      double mean = 0.0;
      for (std::size_t t : set) mean += residuals[t][static_cast<std::size_t>(c) * rows_of(trials[t]) + i] / k;
      for (std::size_t t : set) {
        const std::size_t at = static_cast<std::size_t>(c) * rows_of(trials[t]) + i;
        const double d = residuals[t][at] - mean;
        ss += d * d;
        auto& b = blocks[{t, trials[t].points[at].group}];
        b.first += d;
        ++b.second;
        if (t == set.front()) units.insert(trials[t].points[at].unit);
      }
      ++count;
    }
  }
  RepeatSpread s;
  if (count == 0 || blocks.empty()) return s;
  // Deviations from the mean of K repetitions have (K - 1) / K of the noise's variance.
  s.noise2 = ss / (static_cast<double>(count) * (k - 1.0));
  double bm = 0.0, n = 0.0;
  for (const auto& [key, b] : blocks) {
    bm += std::pow(b.first / b.second, 2);
    n += b.second;
  }
  s.block_mean2 = bm / static_cast<double>(blocks.size()) * k / (k - 1.0);
  s.block_size = n / static_cast<double>(blocks.size());
  s.units = static_cast<int>(units.size());
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

void apply_repeat_noise(std::vector<PreparedTrial>& trials, const std::vector<std::vector<std::size_t>>& sets,
                        const std::vector<std::vector<double>>& residuals) {
  for (const auto& set : sets) {
    const RepeatSpread s = spread_of(trials, residuals, set);
    if (!(s.noise2 > 0.0)) continue;
    for (std::size_t t : set) {
      PreparedTrial& p = trials[t];
      const double noise = std::sqrt(s.noise2);
      if (noise > p.noise) {
        p.noise_source = fmt::format(
            "spread of the nominal residuals across {} repetitions of the task (the "
            "windowed estimate, {:.3g} {}, misses the noise slower than the motion)",
            set.size(), p.noise, p.unit);
        p.noise = noise;
      }
      // A block mean of white noise has noise^2 / n; a sensor's wander leaves far more.
      p.group_inflation = std::max(1.0, s.block_mean2 * s.block_size / (p.noise * p.noise));
      // The deviations' independent pieces: a noise that wanders for seconds makes the blocks of one 4 s unit alike.
      p.noise_dof = std::max(1, (static_cast<int>(set.size()) - 1) * std::max(1, s.units));
    }
  }
}

}  // namespace softwrist::diagnosis
