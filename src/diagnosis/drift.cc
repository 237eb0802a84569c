#include "diagnosis/drift.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace softwrist::diagnosis {
namespace {

// Per repeat group (in the log's order of first appearance): the mean residual of each repetition.
using GroupRepetitions = std::map<int, std::map<int, std::pair<double, int>>>;

GroupRepetitions by_group_and_repetition(const PreparedTrial& trial, const std::vector<double>& predicted) {
  GroupRepetitions groups;
  for (std::size_t i = 0; i < trial.points.size(); ++i) {
    const Point& p = trial.points[i];
    if (p.repetition < 0 || i >= predicted.size() || !std::isfinite(predicted[i])) continue;
    auto& [sum, count] = groups[p.group][p.repetition];
    sum += p.measured - predicted[i];
    ++count;
  }
  return groups;
}

// The sample variance of the means of `batches` contiguous batches of `values`.
double batch_mean_variance(const std::vector<double>& values, std::size_t batches) {
  std::vector<double> means;
  for (std::size_t k = 0; k < batches; ++k) {
    const std::size_t from = k * values.size() / batches, to = (k + 1) * values.size() / batches;
    double sum = 0.0;
    for (std::size_t i = from; i < to; ++i) sum += values[i];
    means.push_back(sum / static_cast<double>(to - from));
  }
  double mean = 0.0, variance = 0.0;
  for (double m : means) mean += m / static_cast<double>(batches);
  for (double m : means) variance += (m - mean) * (m - mean) / static_cast<double>(batches - 1);
  return variance;
}

}  // namespace

std::vector<TrialDrift> drift_across_repetitions(const std::vector<PreparedTrial>& prepared,
                                                 const std::vector<std::vector<double>>& predictions,
                                                 const DriftOptions& options) {
  std::vector<TrialDrift> out;
  for (std::size_t t = 0; t < prepared.size() && t < predictions.size(); ++t) {
    const PreparedTrial& trial = prepared[t];
    std::set<int> repetitions;
    for (const Point& p : trial.points) {
      if (p.repetition >= 0) repetitions.insert(p.repetition);
    }
    if (repetitions.size() < 2 || !(trial.noise > 0.0)) continue;
    const int first = *repetitions.begin(), last = *repetitions.rbegin();
    // The repetition nearest the middle, for the contrast a drift linear in time does not move:
    // r_last - w r_mid + (w - 1) r_first with w = (last - first) / (mid - first).
    int middle = first;
    for (int r : repetitions) {
      if (r != first && r != last && std::abs(2 * r - first - last) < std::abs(2 * middle - first - last)) middle = r;
    }
    const double w = middle != first ? static_cast<double>(last - first) / (middle - first) : 0.0;
    std::vector<double> shifts, contrasts;  // per condition measured in the first and last (and middle) repetition
    for (const auto& [group, by_repetition] : by_group_and_repetition(trial, predictions[t])) {
      const auto a = by_repetition.find(first), b = by_repetition.find(last), m = by_repetition.find(middle);
      if (a == by_repetition.end() || b == by_repetition.end()) continue;
      const double ra = a->second.first / a->second.second, rb = b->second.first / b->second.second;
      shifts.push_back(rb - ra);
      if (middle != first && m != by_repetition.end())
        contrasts.push_back(rb - w * (m->second.first / m->second.second) + (w - 1.0) * ra);
    }
    TrialDrift drift{
        .experiment = trial.name, .first_repetition = first, .last_repetition = last, .conditions = shifts.size()};
    double mean = 0.0;
    for (double s : shifts) mean += s / static_cast<double>(shifts.size());
    drift.shift = shifts.empty() ? 0.0 : mean / trial.noise;
    if (shifts.size() >= options.min_conditions && options.batches >= 2) {
      // The batch means' variance under no drift: from the drift-free contrast where every condition has it (its
      // noise variance is (1 + w^2 + (w - 1)^2) / 2 times the shift's), else from the shifts themselves.
      const bool contrast = contrasts.size() == shifts.size();
      const double variance =
          contrast ? batch_mean_variance(contrasts, options.batches) * 2.0 / (1.0 + w * w + (w - 1.0) * (w - 1.0))
                   : batch_mean_variance(shifts, options.batches);
      drift.t = variance > 0.0 ? mean / std::sqrt(variance / static_cast<double>(options.batches)) : 0.0;
      drift.significant = std::abs(drift.t) >= options.min_t && std::abs(drift.shift) >= options.min_shift;
    }
    out.push_back(drift);
  }
  return out;
}

}  // namespace softwrist::diagnosis
