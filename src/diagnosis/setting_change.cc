#include "diagnosis/setting_change.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "sim/device.h"

namespace softwrist::diagnosis {
namespace {

struct ResidualSum {
  double sum = 0.0;
  int count = 0;
  double mean() const { return sum / count; }
};

// One condition's residuals in the first and the last repetition, and where it was measured.
struct ConditionRepeats {
  ResidualSum first, last;
  int setting = -1, muscle = -1;
  double angle_deg = 0.0;
};

std::map<int, ConditionRepeats> repeats_by_condition(const PreparedTrial& trial, const std::vector<double>& predicted,
                                                     int first, int last) {
  std::map<int, ConditionRepeats> out;
  for (std::size_t i = 0; i < trial.points.size() && i < predicted.size(); ++i) {
    const Point& p = trial.points[i];
    if (p.condition < 0 || !std::isfinite(predicted[i]) || (p.repetition != first && p.repetition != last)) continue;
    ConditionRepeats& c = out[p.condition];
    ResidualSum& s = p.repetition == first ? c.first : c.last;
    s.sum += p.measured - predicted[i];
    ++s.count;
    c.setting = p.unit, c.muscle = p.muscle, c.angle_deg = p.angle_deg;
  }
  return out;
}

// The sample variance of `values` about their mean.
double variance(const std::vector<double>& values) {
  double mean = 0.0, ss = 0.0;
  for (double v : values) mean += v / static_cast<double>(values.size());
  for (double v : values) ss += (v - mean) * (v - mean);
  return ss / static_cast<double>(values.size() - 1);
}

double median(std::vector<double> values) {
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  if (values.size() % 2 == 1) return values[mid];
  return 0.5 * (values[mid] + *std::max_element(values.begin(), values.begin() + static_cast<long>(mid)));
}

struct Setting {
  std::vector<double> differences;
  double angle_deg = 0.0;
};

// One muscle's settings: the one whose repeat differences vary most against the median of the others'.
SettingChange test_settings(const PreparedTrial& trial, int muscle, const std::map<int, Setting>& settings,
                            const SettingChangeOptions& options) {
  SettingChange out{.experiment = trial.name};
  std::vector<std::pair<double, const Setting*>> variances;
  for (const auto& [id, s] : settings) {
    if (s.differences.size() >= std::max<std::size_t>(options.min_conditions, 2))
      variances.emplace_back(variance(s.differences), &s);
  }
  out.settings = variances.size();
  if (variances.size() < std::max<std::size_t>(options.min_settings, 2)) return out;
  const auto largest = std::max_element(variances.begin(), variances.end(),
                                        [](const auto& a, const auto& b) { return a.first < b.first; });
  // The other settings whose repeats differ at all: a setting that reads the same to the last digit twice (an unloaded
  // angle through a coarse sensor) says nothing of the noise, and a majority of them would make any change infinite.
  std::vector<double> others;
  for (auto it = variances.begin(); it != variances.end(); ++it) {
    if (it != largest && it->first > 0.0) others.push_back(it->first);
  }
  out.settings = others.size() + 1;
  if (out.settings < std::max<std::size_t>(options.min_settings, 2)) return out;
  const double reference = median(others);
  if (muscle >= 0 && muscle < static_cast<int>(sim::kMuscleNames.size()))
    out.muscle = sim::kMuscleNames[static_cast<std::size_t>(muscle)];
  out.angle_deg = largest->second->angle_deg;
  out.conditions = largest->second->differences.size();
  out.spread = std::sqrt(largest->first);
  out.spread_noise_units = out.spread / trial.noise;
  out.unit = trial.unit;
  out.ratio = largest->first / reference;
  out.significant = out.ratio >= options.min_ratio;
  return out;
}

}  // namespace

std::vector<SettingChange> change_at_one_setting(const std::vector<PreparedTrial>& prepared,
                                                 const std::vector<std::vector<double>>& predictions,
                                                 const SettingChangeOptions& options) {
  std::vector<SettingChange> out;
  for (std::size_t t = 0; t < prepared.size() && t < predictions.size(); ++t) {
    const PreparedTrial& trial = prepared[t];
    std::set<int> repetitions;
    for (const Point& p : trial.points) {
      if (p.condition >= 0 && p.repetition >= 0) repetitions.insert(p.repetition);
    }
    if (repetitions.size() < 2 || !(trial.noise > 0.0)) continue;
    const int first = *repetitions.begin(), last = *repetitions.rbegin();
    // Each muscle's settings apart: a stronger muscle's repeats differ more at every setting (a hysteresis scales with
    // its pull), which against a weaker one's median would read as a change.
    std::map<int, std::map<int, Setting>> by_muscle;
    for (const auto& [condition, c] : repeats_by_condition(trial, predictions[t], first, last)) {
      if (c.first.count == 0 || c.last.count == 0) continue;
      Setting& s = by_muscle[c.muscle][c.setting];
      s.differences.push_back(c.last.mean() - c.first.mean());
      s.angle_deg = c.angle_deg;
    }
    SettingChange change{.experiment = trial.name};
    for (const auto& [muscle, settings] : by_muscle) {
      const SettingChange own = test_settings(trial, muscle, settings, options);
      if (own.ratio > change.ratio || (change.settings == 0 && own.settings > 0)) change = own;
    }
    change.first_repetition = first, change.last_repetition = last;
    out.push_back(change);
  }
  return out;
}

}  // namespace softwrist::diagnosis
