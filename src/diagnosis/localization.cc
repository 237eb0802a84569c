#include "diagnosis/localization.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <map>
#include <numeric>

#include <fmt/format.h>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <unsupported/Eigen/FFT>

#include "diagnosis/setting_scatter.h"
#include "physics/torque_geometry.h"
#include "physics/units.h"
#include "sim/wrist_sim.h"

namespace softwrist::diagnosis {

double f_test_p_value(double f, double d1, double d2) {
  if (!(f > 0.0) || d1 <= 0.0 || d2 <= 0.0) return 1.0;
  return boost::math::cdf(boost::math::complement(boost::math::fisher_f(d1, d2), f));
}

double chi_squared_p_value(double x, double k) {
  if (!(x > 0.0) || k <= 0.0) return 1.0;
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared(k), x));
}

std::vector<bool> holm_significant(const std::vector<double>& p_values, double alpha) {
  const std::size_t m = p_values.size();
  std::vector<std::size_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  // NaNs last: a test that gave no p rejects nothing, and stops the procedure where it is reached.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return !std::isnan(p_values[a]) && (std::isnan(p_values[b]) || p_values[a] < p_values[b]);
  });
  std::vector<bool> significant(m, false);
  for (std::size_t k = 0; k < m; ++k) {
    const double p = p_values[order[k]];
    if (!(p < alpha / static_cast<double>(m - k))) break;
    significant[order[k]] = true;
  }
  return significant;
}

LocalizationEntry group_test(const PreparedTrial& trial, const std::vector<double>& residuals,
                             const std::vector<std::size_t>& members) {
  std::map<int, std::pair<double, int>> groups;
  for (std::size_t i : members) {
    auto& g = groups[trial.points[i].group];
    g.first += residuals[i];
    ++g.second;
  }
  double weighted = 0.0;  // sum n_g r_g^2
  int n = 0;
  for (const auto& [id, g] : groups) {
    weighted += g.first * g.first / g.second;
    n += g.second;
  }
  LocalizationEntry e{.experiment = trial.name, .unit = trial.unit, .count = n};
  const double k = static_cast<double>(groups.size());
  if (n == 0 || trial.noise <= 0.0) return e;
  e.residual = std::sqrt(weighted / n);
  const double group_noise2 = trial.noise * trial.noise * trial.group_inflation;  // n x a group mean's variance
  e.noise = std::sqrt(group_noise2 * k / n);
  e.p_value = f_test_p_value(weighted / (k * group_noise2), k, trial.noise_dof);
  return e;
}

namespace {

using Members = std::vector<std::size_t>;

// Partition of a trial's points by a key (points mapping to nullopt are left out).
template <class Key>
std::map<Key, Members> split(const PreparedTrial& trial, const std::function<std::optional<Key>(const Point&)>& key) {
  std::map<Key, Members> parts;
  for (std::size_t i = 0; i < trial.points.size(); ++i) {
    if (auto k = key(trial.points[i])) parts[*k].push_back(i);
  }
  return parts;
}

std::string channel_name(int channel) {
  if (channel >= 2) return fmt::format("{} pressure", sim::kMuscleNames[static_cast<std::size_t>(channel - 2)]);
  return channel == 0 ? "flexion/extension" : "ulnar/radial";
}

// The residual's frequency bands of one trajectory channel.
void add_bands(const PreparedTrial& trial, const std::vector<double>& residuals, int channel,
               std::vector<LocalizationEntry>& out) {
  std::vector<double> r;
  std::vector<double> t;
  for (std::size_t i = 0; i < trial.points.size(); ++i) {
    if (trial.points[i].channel == channel) {
      r.push_back(residuals[i]);
      t.push_back(trial.points[i].t_s);
    }
  }
  const std::size_t n = r.size();
  if (n < 16 || trial.noise <= 0.0) return;
  const double dt = (t.back() - t.front()) / static_cast<double>(n - 1);  // the log's rows are (nearly) uniform
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, r);
  struct Band {
    double lo, hi;
    const char* name;
  };
  for (const Band band : {Band{0.0, 0.1, "below 0.1 Hz"}, Band{0.1, 1.0, "0.1-1 Hz"}, Band{1.0, 1e9, "above 1 Hz"}}) {
    double power = 0.0;
    int bins = 0;
    for (std::size_t k = 1; k < n / 2; ++k) {  // one-sided, without the mean (bin 0) and Nyquist
      const double f = static_cast<double>(k) / (static_cast<double>(n) * dt);
      if (f < band.lo || f >= band.hi) continue;
      power += std::norm(spectrum[k]);
      ++bins;
    }
    if (bins == 0) continue;
    // A wandering noise's power lies below the 1 s blocks' rate (group_inflation is measured there); above it the
    // noise is taken as white.
    const double sigma2 = trial.noise * trial.noise * (band.hi <= 1.0 ? trial.group_inflation : 1.0);
    const double nn = static_cast<double>(n);
    LocalizationEntry e{.experiment = trial.name,
                        .where = fmt::format("{} {}", channel_name(channel), band.name),
                        .residual = std::sqrt(2.0 * power) / nn,
                        .noise = std::sqrt(sigma2 * 2.0 * bins / nn),
                        .unit = trial.unit,
                        .count = static_cast<int>(n)};
    e.p_value = chi_squared_p_value(2.0 * power / (nn * sigma2), 2.0 * bins);
    out.push_back(e);
  }
}

// Where the entries of one trial go: each the group test of some of its points.
struct TrialEntries {
  const PreparedTrial& trial;
  const std::vector<double>& residuals;
  std::vector<LocalizationEntry>& out;

  void add(const Members& members, std::string where, double angle = NAN, double pressure = NAN) const {
    LocalizationEntry e = group_test(trial, residuals, members);
    e.where = std::move(where);
    e.angle_deg = angle;
    e.pressure_kpa = pressure;
    out.push_back(std::move(e));
  }
};

// Whether the nominal device's `muscle` wraps around the wrist at `angle_deg`.
bool nominal_path_wraps(const sim::DeviceDescription& nominal, int muscle, double angle_deg) {
  const auto& mount = nominal.muscles[static_cast<std::size_t>(muscle)];
  return physics::muscle_path(
             mount.placement, mount.wrist_radius,
             physics::direction_of(static_cast<sim::MuscleIndex>(muscle)) * units::deg_to_rad(angle_deg),
             mount.wrap_surface)
             .regime == physics::Regime::kWrapping;
}

// Each held angle (the mean of its cluster), and each regime of the nominal path.
void add_held_angles(const TrialEntries& entries, const sim::DeviceDescription& nominal) {
  const PreparedTrial& trial = entries.trial;
  std::map<int, std::pair<double, Members>> by_unit;
  for (std::size_t i = 0; i < trial.points.size(); ++i) {
    auto& u = by_unit[trial.points[i].unit];
    u.first += trial.points[i].angle_deg;
    u.second.push_back(i);
  }
  std::map<bool, Members> by_regime;
  for (auto& [unit, u] : by_unit) {
    const double angle = u.first / static_cast<double>(u.second.size());
    const int muscle = trial.points[u.second.front()].muscle;
    const bool wrapping = nominal_path_wraps(nominal, muscle, angle);
    entries.add(u.second,
                fmt::format("{} angle {:.1f} deg ({})", sim::kMuscleNames[static_cast<std::size_t>(muscle)], angle,
                            wrapping ? "wrapping" : "straight"),
                angle);
    auto& regime = by_regime[wrapping];
    regime.insert(regime.end(), u.second.begin(), u.second.end());
  }
  for (const auto& [wrapping, members] : by_regime) {
    entries.add(members, wrapping ? "wrapping regime" : "straight regime");
  }
}

void add_pressures(const TrialEntries& entries) {
  for (const auto& [kpa, members] :
       split<long>(entries.trial, [](const Point& p) { return std::lround(p.pressure_kpa); })) {
    entries.add(members, fmt::format("pressure {} kPa", kpa), NAN, static_cast<double>(kpa));
  }
}

// The residual map: each held angle at each pressure.
void add_residual_map(const TrialEntries& entries) {
  const PreparedTrial& trial = entries.trial;
  for (const auto& [group, members] : split<int>(trial, [](const Point& p) { return p.group; })) {
    double angle = 0.0;
    for (std::size_t i : members) angle += trial.points[i].angle_deg;
    angle /= static_cast<double>(members.size());
    const double kpa = trial.points[members.front()].pressure_kpa;
    entries.add(members, fmt::format("angle {:.1f} deg at {:.0f} kPa", angle, kpa), angle, kpa);
  }
}

void add_range_of_motion_muscles(const TrialEntries& entries) {
  for (const auto& [muscle, members] : split<int>(entries.trial, [](const Point& p) { return p.muscle; })) {
    entries.add(members, fmt::format("{} muscle", sim::kMuscleNames[static_cast<std::size_t>(muscle)]));
  }
}

void add_tensile_motions_and_contractions(const TrialEntries& entries) {
  for (const auto& [motion, members] : split<int>(entries.trial, [](const Point& p) { return p.motion; })) {
    entries.add(members, motion > 0 ? "loading" : "unloading");
  }
  for (const auto& [bin, members] :
       split<long>(entries.trial, [](const Point& p) { return std::lround(std::floor(p.contraction / 0.05)); })) {
    entries.add(members, fmt::format("contraction {:.2f}-{:.2f}", 0.05 * bin, 0.05 * (bin + 1)));
  }
}

// Each muscle's regulator: filling, venting, holding, and the frequency bands.
void add_pressure_channels(const TrialEntries& entries) {
  for (int channel = 2; channel < 6; ++channel) {
    for (const auto& [motion, members] : split<int>(entries.trial, [&](const Point& p) -> std::optional<int> {
           if (p.channel != channel) return std::nullopt;
           return p.motion;
         })) {
      entries.add(members, fmt::format("{} {}", channel_name(channel),
                                       motion == 0 ? "steady" : (motion > 0 ? "filling" : "venting")));
    }
    add_bands(entries.trial, entries.residuals, channel, entries.out);
  }
}

// Each angle axis: 10-degree bins of the angle, the direction of motion, and the frequency bands.
void add_angle_channels(const TrialEntries& entries) {
  for (int channel = 0; channel < 2; ++channel) {
    const auto in_channel = [channel](const Point& p) { return p.channel == channel; };
    for (const auto& [bin, members] : split<long>(entries.trial, [&](const Point& p) -> std::optional<long> {
           if (!in_channel(p)) return std::nullopt;
           return std::lround(std::floor(p.angle_deg / 10.0));
         })) {
      entries.add(members, fmt::format("{} {} to {} deg", channel_name(channel), 10 * bin, 10 * (bin + 1)),
                  10.0 * static_cast<double>(bin) + 5.0);
    }
    for (const auto& [motion, members] : split<int>(entries.trial, [&](const Point& p) -> std::optional<int> {
           if (!in_channel(p)) return std::nullopt;
           return p.motion;
         })) {
      const char* direction = motion == 0 ? "at rest"
                                          : (motion > 0 ? (channel == 0 ? "flexing" : "moving ulnar")
                                                        : (channel == 0 ? "extending" : "moving radial"));
      entries.add(members, fmt::format("{} {}", channel_name(channel), direction));
    }
    add_bands(entries.trial, entries.residuals, channel, entries.out);
  }
}

void add_trial_entries(const TrialEntries& entries, const sim::DeviceDescription& nominal) {
  Members all(entries.trial.points.size());
  std::iota(all.begin(), all.end(), 0);
  entries.add(all, "all");
  switch (entries.trial.trial->kind) {
    case TrialKind::kTorqueSweep:
      add_held_angles(entries, nominal);
      add_pressures(entries);
      add_residual_map(entries);
      break;
    case TrialKind::kRangeOfMotion:
      add_range_of_motion_muscles(entries);
      break;
    case TrialKind::kTensile:
      add_pressures(entries);
      add_tensile_motions_and_contractions(entries);
      break;
    case TrialKind::kTrajectory:
      if (entries.trial.pressures) {
        add_pressure_channels(entries);
      } else {
        add_angle_channels(entries);
      }
      break;
  }
}

}  // namespace

std::vector<LocalizationEntry> localize(const std::vector<PreparedTrial>& trials,
                                        const std::vector<std::vector<double>>& residuals,
                                        const sim::DeviceDescription& nominal, double alpha) {
  std::vector<LocalizationEntry> out;
  for (std::size_t ti = 0; ti < trials.size(); ++ti) {
    // A sweep's setting offsets weighed as what they are (setting_scatter.h), as in the trial's own gap test.
    const std::vector<double> white = whitened(trials[ti], residuals[ti]);
    add_trial_entries({trials[ti], white, out}, nominal);
  }
  const double tests = static_cast<double>(std::max<std::size_t>(1, out.size()));
  for (auto& e : out) e.significant = e.p_value < alpha / tests;
  std::stable_sort(out.begin(), out.end(), [](const LocalizationEntry& a, const LocalizationEntry& b) {
    const double za = a.noise > 0 ? a.residual / a.noise : 0.0, zb = b.noise > 0 ? b.residual / b.noise : 0.0;
    return za > zb;
  });
  return out;
}

}  // namespace softwrist::diagnosis
