#include "diagnosis/drift.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace softwrist::diagnosis {
namespace {

// Per repeat group: the mean residual of each repetition.
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

}  // namespace

std::vector<TrialDrift> drift_across_repetitions(const std::vector<PreparedTrial>& prepared,
                                                 const std::vector<std::vector<double>>& predictions,
                                                 const DriftOptions& options) {
  std::vector<TrialDrift> out;
  for (std::size_t t = 0; t < prepared.size() && t < predictions.size(); ++t) {
    const PreparedTrial& trial = prepared[t];
    int first = 0, last = -1;
    bool any = false;
    for (const Point& p : trial.points) {
      if (p.repetition < 0) continue;
      first = any ? std::min(first, p.repetition) : p.repetition;
      last = any ? std::max(last, p.repetition) : p.repetition;
      any = true;
    }
    if (!any || first == last || !(trial.noise > 0.0)) continue;
    std::vector<double> shifts;  // last less first, per condition measured in both
    for (const auto& [group, repetitions] : by_group_and_repetition(trial, predictions[t])) {
      const auto a = repetitions.find(first), b = repetitions.find(last);
      if (a == repetitions.end() || b == repetitions.end()) continue;
      shifts.push_back(b->second.first / b->second.second - a->second.first / a->second.second);
    }
    TrialDrift drift{
        .experiment = trial.name, .first_repetition = first, .last_repetition = last, .conditions = shifts.size()};
    if (!shifts.empty()) {
      double mean = 0.0;
      for (double s : shifts) mean += s / static_cast<double>(shifts.size());
      drift.shift = mean / trial.noise;
    }
    if (shifts.size() >= options.min_conditions && options.batches >= 2) {
      const double mean = drift.shift * trial.noise, b = static_cast<double>(options.batches);
      double variance = 0.0;  // of the batch means about the mean
      for (std::size_t k = 0; k < options.batches; ++k) {
        const std::size_t from = k * shifts.size() / options.batches, to = (k + 1) * shifts.size() / options.batches;
        double batch = 0.0;
        for (std::size_t i = from; i < to; ++i) batch += shifts[i] / static_cast<double>(to - from);
        variance += (batch - mean) * (batch - mean) / (b - 1.0);
      }
      drift.t = variance > 0.0 ? mean / std::sqrt(variance / b) : 0.0;
      drift.significant = std::abs(drift.t) >= options.min_t && std::abs(drift.shift) >= options.min_shift;
    }
    out.push_back(drift);
  }
  return out;
}

}  // namespace softwrist::diagnosis
