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
