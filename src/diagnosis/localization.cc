#include "diagnosis/localization.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <map>
#include <numeric>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <fmt/format.h>
#include <unsupported/Eigen/FFT>

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
  e.noise = trial.noise * std::sqrt(k / n);
  e.p_value = f_test_p_value(weighted / (k * trial.noise * trial.noise), k, trial.noise_dof);
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
    const double sigma2 = trial.noise * trial.noise;
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

}  // namespace

std::vector<LocalizationEntry> localize(const std::vector<PreparedTrial>& trials,
                                        const std::vector<std::vector<double>>& residuals,
                                        const sim::DeviceDescription& nominal, double alpha) {
  std::vector<LocalizationEntry> out;
  const auto add = [&](const PreparedTrial& trial, const std::vector<double>& r, const Members& members,
                       std::string where, double angle = NAN, double pressure = NAN) {
    LocalizationEntry e = group_test(trial, r, members);
    e.where = std::move(where);
    e.angle_deg = angle;
    e.pressure_kpa = pressure;
    out.push_back(std::move(e));
  };
  for (std::size_t ti = 0; ti < trials.size(); ++ti) {
    const PreparedTrial& trial = trials[ti];
    const std::vector<double>& r = residuals[ti];
    Members all(trial.points.size());
    std::iota(all.begin(), all.end(), 0);
    add(trial, r, all, "all");
    switch (trial.trial->kind) {
      case TrialKind::kTorqueSweep: {
        // Each held angle (the mean of its cluster), pressure, and regime of the nominal path.
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
          const auto& mount = nominal.muscles[static_cast<std::size_t>(muscle)];
          const bool wrapping =
              physics::muscle_path(mount.placement, mount.wrist_radius,
                                   sim::direction_of(static_cast<sim::MuscleIndex>(muscle)) *
                                       units::deg_to_rad(angle))
                  .regime == physics::Regime::kWrapping;
          add(trial, r, u.second,
              fmt::format("{} angle {:.1f} deg ({})", sim::kMuscleNames[static_cast<std::size_t>(muscle)], angle,
                          wrapping ? "wrapping" : "straight"),
              angle);
          auto& regime = by_regime[wrapping];
          regime.insert(regime.end(), u.second.begin(), u.second.end());
        }
        for (const auto& [wrapping, members] : by_regime) add(trial, r, members, wrapping ? "wrapping regime" : "straight regime");
        for (const auto& [kpa, members] : split<long>(trial, [](const Point& p) { return std::lround(p.pressure_kpa); })) {
          add(trial, r, members, fmt::format("pressure {} kPa", kpa), NAN, static_cast<double>(kpa));
        }
        // The residual map: each held angle at each pressure.
        for (const auto& [group, members] : split<int>(trial, [](const Point& p) { return p.group; })) {
          double angle = 0.0;
          for (std::size_t i : members) angle += trial.points[i].angle_deg;
          angle /= static_cast<double>(members.size());
          const double kpa = trial.points[members.front()].pressure_kpa;
          add(trial, r, members, fmt::format("angle {:.1f} deg at {:.0f} kPa", angle, kpa), angle, kpa);
        }
        break;
      }
      case TrialKind::kRangeOfMotion:
        for (const auto& [muscle, members] : split<int>(trial, [](const Point& p) { return p.muscle; })) {
          add(trial, r, members, fmt::format("{} muscle", sim::kMuscleNames[static_cast<std::size_t>(muscle)]));
        }
        break;
      case TrialKind::kTensile:
        for (const auto& [kpa, members] : split<long>(trial, [](const Point& p) { return std::lround(p.pressure_kpa); })) {
          add(trial, r, members, fmt::format("pressure {} kPa", kpa), NAN, static_cast<double>(kpa));
        }
        for (const auto& [motion, members] : split<int>(trial, [](const Point& p) { return p.motion; })) {
          add(trial, r, members, motion > 0 ? "loading" : "unloading");
        }
        for (const auto& [bin, members] :
             split<long>(trial, [](const Point& p) { return std::lround(std::floor(p.contraction / 0.05)); })) {
          add(trial, r, members, fmt::format("contraction {:.2f}-{:.2f}", 0.05 * bin, 0.05 * (bin + 1)));
        }
        break;
      case TrialKind::kTrajectory:
        if (trial.pressures) {  // each muscle's regulator: filling, venting, holding, and the frequency bands
          for (int channel = 2; channel < 6; ++channel) {
            for (const auto& [motion, members] : split<int>(trial, [&](const Point& p) -> std::optional<int> {
                   if (p.channel != channel) return std::nullopt;
                   return p.motion;
                 })) {
              add(trial, r, members,
                  fmt::format("{} {}", channel_name(channel), motion == 0 ? "steady" : (motion > 0 ? "filling" : "venting")));
            }
            add_bands(trial, r, channel, out);
          }
          break;
        }
        for (int channel = 0; channel < 2; ++channel) {
          const auto in_channel = [channel](const Point& p) { return p.channel == channel; };
          for (const auto& [bin, members] : split<long>(trial, [&](const Point& p) -> std::optional<long> {
                 if (!in_channel(p)) return std::nullopt;
                 return std::lround(std::floor(p.angle_deg / 10.0));
               })) {
            add(trial, r, members, fmt::format("{} {} to {} deg", channel_name(channel), 10 * bin, 10 * (bin + 1)),
                10.0 * static_cast<double>(bin) + 5.0);
          }
          for (const auto& [motion, members] : split<int>(trial, [&](const Point& p) -> std::optional<int> {
                 if (!in_channel(p)) return std::nullopt;
                 return p.motion;
               })) {
            const char* direction = motion == 0 ? "at rest" : (motion > 0 ? (channel == 0 ? "flexing" : "moving ulnar")
                                                                          : (channel == 0 ? "extending" : "moving radial"));
            add(trial, r, members, fmt::format("{} {}", channel_name(channel), direction));
          }
          add_bands(trial, r, channel, out);
        }
        break;
    }
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
