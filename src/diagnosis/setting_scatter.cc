#include "diagnosis/setting_scatter.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>

namespace softwrist::diagnosis {
namespace {

// One setting's readings: where it was held and the sum of their residuals.
struct Setting {
  int station = -1;  // the held angle of one muscle (Point::unit of a sweep)
  int muscle = -1;
  int repetition = -1;
  double angle_sum = 0.0;
  double sum = 0.0;
  int n = 0;
  double angle_deg() const { return angle_sum / n; }
  double mean() const { return sum / n; }
};

std::vector<Setting> settings_of(const PreparedTrial& trial, const std::vector<double>& residuals) {
  std::vector<Setting> settings;
  for (std::size_t i = 0; i < std::min(trial.points.size(), residuals.size()); ++i) {
    const Point& p = trial.points[i];
    if (p.setting < 0 || !std::isfinite(residuals[i])) continue;
    if (settings.size() <= static_cast<std::size_t>(p.setting))
      settings.resize(static_cast<std::size_t>(p.setting) + 1);
    Setting& s = settings[static_cast<std::size_t>(p.setting)];
    s.station = p.unit;
    s.muscle = p.muscle;
    s.repetition = p.repetition;
    s.angle_sum += p.angle_deg;
    s.sum += residuals[i];
    ++s.n;
  }
  std::erase_if(settings, [](const Setting& s) { return s.n == 0; });
  return settings;
}

// The variance of a setting's mean: a sum of squares and its degrees of freedom.
struct MeanVariance {
  double ss = 0.0;
  int dof = 0;
};

// From held angles set more than once: the spread of their settings' means about the held angle's mean.
MeanVariance across_repeated_settings(const std::vector<Setting>& settings) {
  std::map<int, std::vector<double>> by_station;
  for (const Setting& s : settings) by_station[s.station].push_back(s.mean());
  MeanVariance v;
  for (const auto& [station, means] : by_station) {
    if (means.size() < 2) continue;
    double mean = 0.0;
    for (double m : means) mean += m / static_cast<double>(means.size());
    for (double m : means) v.ss += (m - mean) * (m - mean);
    v.dof += static_cast<int>(means.size()) - 1;
  }
  return v;
}

// From each sequence of settings (one muscle, one repetition): the settings' means about a quadratic in angle, which
// takes a model error smooth in angle (a relaxed wrist's stiffness, linear; its stiffening towards both limits,
// about quadratic) and leaves the scatter with K - 3 degrees of freedom for K settings.
MeanVariance about_a_quadratic_in_angle(const std::vector<Setting>& settings) {
  std::map<std::pair<int, int>, std::vector<const Setting*>> sequences;
  for (const Setting& s : settings) sequences[{s.muscle, s.repetition}].push_back(&s);
  MeanVariance v;
  for (const auto& [key, seq] : sequences) {
    if (seq.size() < 4) continue;
    Eigen::MatrixXd a(seq.size(), 3);
    Eigen::VectorXd m(seq.size());
    for (std::size_t k = 0; k < seq.size(); ++k) {
      const double x = seq[k]->angle_deg() / 90.0;
      a.row(static_cast<Eigen::Index>(k)) << 1.0, x, x * x;
      m(static_cast<Eigen::Index>(k)) = seq[k]->mean();
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
    if (qr.rank() < 3) continue;  // fewer than three distinct angles
    v.ss += (m - a * qr.solve(m)).squaredNorm();
    v.dof += static_cast<int>(seq.size()) - 3;
  }
  return v;
}

// The upper bound of a one-sided interval (kSettingScatterConfidence) of a variance estimated as ss / dof: ss over
// chi^2_dof's lower quantile.
// A setting's mean is weighed by an estimate from a handful of settings, as often too low as too high, and one too
// low counts the setting's offset as a gap: at the estimate itself a right model's sweep failed the 1 % gap test 10
// times in 400, at the bound once (setting_scatter_test).
double upper_bound(const MeanVariance& v) {
  return v.ss / boost::math::quantile(boost::math::chi_squared(v.dof), 1.0 - kSettingScatterConfidence);
}

}  // namespace

void estimate_setting_scatter(PreparedTrial& trial, const std::vector<double>& residuals) {
  trial.setting_scatter = 0.0;
  const std::vector<Setting> settings = settings_of(trial, residuals);
  if (settings.empty() || !(trial.noise > 0.0)) return;
  if (std::none_of(settings.begin(), settings.end(), [](const Setting& s) { return s.n >= 2; })) return;
  MeanVariance v = across_repeated_settings(settings);
  std::string how = "the spread of the settings of one held angle";
  if (v.dof < 2) {
    v = about_a_quadratic_in_angle(settings);
    how = "the settings about a quadratic in angle";
  }
  if (v.dof < 2) return;
  double inverse_n = 0.0;  // a setting mean's share of the reading noise, noise^2 / n, at the harmonic mean of n
  for (const Setting& s : settings) inverse_n += 1.0 / (s.n * static_cast<double>(settings.size()));
  const double scatter2 = upper_bound(v) - trial.noise * trial.noise * inverse_n;
  if (!(scatter2 > 0.0)) return;
  trial.setting_scatter = std::sqrt(scatter2);
  trial.noise_source += fmt::format(
      "; the readings of one setting share an offset of {:.3g} {} (from {}, {} degrees of freedom, at the upper end "
      "of its {:.0f} % interval)",
      trial.setting_scatter, trial.unit, how, v.dof, 100.0 * kSettingScatterConfidence);
}

std::vector<double> whitened(const PreparedTrial& trial, std::vector<double> residuals, SplitPart part) {
  if (!(trial.setting_scatter > 0.0) || !(trial.noise > 0.0)) return residuals;
  const auto in_part = [part](const Point& p) {
    return p.setting >= 0 && (part == SplitPart::kAll || p.heldout == (part == SplitPart::kHeldOut));
  };
  const std::size_t n_points = std::min(trial.points.size(), residuals.size());  // a training replay may stop early
  std::vector<std::pair<double, int>> sums;
  for (std::size_t i = 0; i < n_points; ++i) {
    const Point& p = trial.points[i];
    if (!in_part(p)) continue;
    if (sums.size() <= static_cast<std::size_t>(p.setting)) sums.resize(static_cast<std::size_t>(p.setting) + 1);
    sums[static_cast<std::size_t>(p.setting)].first += residuals[i];
    ++sums[static_cast<std::size_t>(p.setting)].second;
  }
  const double noise2 = trial.noise * trial.noise, scatter2 = trial.setting_scatter * trial.setting_scatter;
  for (std::size_t i = 0; i < n_points; ++i) {
    const Point& p = trial.points[i];
    if (!in_part(p)) continue;
    const auto& [sum, n] = sums[static_cast<std::size_t>(p.setting)];
    const double shrink = std::sqrt(noise2 / (noise2 + n * scatter2));
    residuals[i] -= (1.0 - shrink) * sum / n;
  }
  return residuals;
}

}  // namespace softwrist::diagnosis
