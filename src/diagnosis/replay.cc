#include "diagnosis/replay.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <Eigen/Dense>

#include "diagnosis/repeat_noise.h"
#include "diagnosis/setting_scatter.h"
#include "physics/fpam_force.h"
#include "physics/fpam_hysteresis.h"
#include "physics/pressure_regulator.h"
#include "physics/units.h"
#include "sim/model.h"
#include "sim/model_builder.h"
#include "sim/simulated_plant.h"
#include "sim/wrist_sim.h"
#include "sim/wrist_statics.h"

namespace softwrist::diagnosis {
namespace {

using units::pa_to_kpa;
using units::rad_to_deg;

constexpr double kTrajectoryGroup = 1.0;  // [s] a repeat group of a trajectory: samples whose systematic part is alike
constexpr double kTrajectoryUnit = 4.0;   // [s] a bootstrap unit
// Samples in a window of the windowed noise estimate: 0.35 s at the paper's 14 ms loop, short enough that a
// quadratic follows the wrist's motion, long enough that the noise's own correlation (tens of ms) stays inside it.
constexpr std::size_t kNoiseWindow = 25;
constexpr double kRomSettle = 6.0;  // [s] the range-of-motion experiment's settling time
// [s] a trajectory whose angles were zeroed at its start is replayed from the wrist settled under its first command
// this long: the real trial began wherever the wrist rested, not necessarily at the model's neutral angle.
constexpr double kPreSettle = 2.0;
// [kPa] the resolution of a logged measured pressure (the bridge protocol's 0.1 kPa, docs/bridge-protocol.md): its
// quantisation noise, resolution / sqrt(12), is the least noise a pressure trial is weighed with, so a smooth,
// noise-free log does not make every rounding error significant.
constexpr double kPressureResolutionKpa = 0.1;

// Dense ids for arbitrary keys, in order of first appearance.
template <class Key>
class Ids {
 public:
  int operator()(const Key& key) { return ids_.try_emplace(key, static_cast<int>(ids_.size())).first->second; }
  int count() const { return static_cast<int>(ids_.size()); }

 private:
  std::map<Key, int> ids_;
};

// A noise estimate: its standard deviation and degrees of freedom.
struct Spread {
  double sd = 0.0;
  int dof = 0;
};

// The pooled spread of `residuals` about their means within the groups a point's `group` field names (points of group
// -1 left out).
Spread pooled_spread(const PreparedTrial& prepared, const std::vector<double>& residuals, int Point::*group) {
  std::map<int, std::pair<double, int>> sums;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    const int g = prepared.points[i].*group;
    if (g < 0) continue;
    sums[g].first += residuals[i];
    ++sums[g].second;
  }
  double ss = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    const int g = prepared.points[i].*group;
    if (g < 0) continue;
    const auto& s = sums[g];
    ss += std::pow(residuals[i] - s.first / s.second, 2);
    ++n;
  }
  const int dof = n - static_cast<int>(sums.size());
  return dof >= 1 ? Spread{std::sqrt(ss / dof), dof} : Spread{};
}

// The spread of `residuals` about an additive fit, at each held angle of a torque sweep, of an offset per setting
// (Point::setting) and a value per condition (`condition`): what is left differs from reading to reading within a
// setting, the noise the readings' own (setting_scatter.h). Fitted by alternating the two sets of means (a complete
// table needs one pass; an incomplete one converges), with n - settings - conditions + 1 degrees of freedom per held
// angle.
Spread spread_within_settings(const PreparedTrial& prepared, const std::vector<double>& residuals,
                              int Point::*condition) {
  std::map<int, std::vector<std::size_t>> stations;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    const Point& p = prepared.points[i];
    if (p.setting >= 0 && p.*condition >= 0) stations[p.unit].push_back(i);
  }
  double ss = 0.0;
  int dof = 0;
  for (const auto& [station, members] : stations) {
    std::map<int, std::pair<double, int>> by_setting, by_condition;
    std::vector<double> e;
    for (std::size_t i : members) e.push_back(residuals[i]);
    for (int pass = 0; pass < 50; ++pass) {
      for (int Point::*factor : {&Point::setting, condition}) {
        std::map<int, std::pair<double, int>>& sums = factor == condition ? by_condition : by_setting;
        sums.clear();
        for (std::size_t k = 0; k < members.size(); ++k) {
          auto& s = sums[prepared.points[members[k]].*factor];
          s.first += e[k];
          ++s.second;
        }
        for (std::size_t k = 0; k < members.size(); ++k) {
          const auto& s = sums[prepared.points[members[k]].*factor];
          e[k] -= s.first / s.second;
        }
      }
    }
    const int station_dof =
        static_cast<int>(members.size()) - static_cast<int>(by_setting.size() + by_condition.size()) + 1;
    if (station_dof < 1) continue;
    for (double v : e) ss += v * v;
    dof += station_dof;
  }
  return dof >= 1 ? Spread{std::sqrt(ss / dof), dof} : Spread{};
}

// The successive differences' estimate (in file order), of pairs within one setting only where `within_settings`.
Spread successive_differences(const PreparedTrial& prepared, const std::vector<double>& residuals,
                              bool within_settings) {
  double ss = 0.0;
  int pairs = 0;
  for (std::size_t i = 1; i < residuals.size(); ++i) {
    const int setting = prepared.points[i].setting;
    if (within_settings && (setting < 0 || setting != prepared.points[i - 1].setting)) continue;
    ss += std::pow(residuals[i] - residuals[i - 1], 2);
    ++pairs;
  }
  const int dof = std::max(1, pairs);
  return Spread{std::sqrt(ss / (2.0 * dof)), dof};
}

// Pooled within-group variance of `residuals`. Without repeats: successive differences (in file order), or, where
// it is smaller, the spread between repetitions of a condition reached from either side (Point::condition: a
// torque sweep whose order alternates between repetitions). Each of the two also holds systematic error (the model's
// misfit from one point to the next, the fabric's hysteresis between the two sides), so neither is below the noise
// but by chance; the smaller is the nearer (the choice biases it low by a few per cent where both are the noise). The
// successive differences alone read 0.06-0.3 N m on the independent device's alternating sweeps of a muscle with an
// effect, whose sensor's noise is a few mN m (issue 20's seed 2). A torque sweep's readings of one setting share an
// offset (setting_scatter.h), which each estimate takes out first where some setting holds two readings in a row:
// the noise is then the readings' own, and the offset's spread is estimated and weighed apart.
void estimate_noise(PreparedTrial& prepared, const std::vector<double>& residuals) {
  const Spread within_settings = successive_differences(prepared, residuals, true);
  const bool by_setting = within_settings.dof >= 2;  // two pairs of readings within a setting
  const auto spread = [&](int Point::*condition) {
    return by_setting ? spread_within_settings(prepared, residuals, condition)
                      : pooled_spread(prepared, residuals, condition);
  };
  const std::string about = by_setting ? " about their settings' offsets" : "";
  const Spread repeated = spread(&Point::group);
  if (repeated.dof >= 2) {
    prepared.noise = repeated.sd;
    prepared.noise_dof = repeated.dof;
    prepared.noise_source = "pooled spread of repeated measurements" + about;
    return;
  }
  const Spread successive = by_setting ? within_settings : successive_differences(prepared, residuals, false);
  const std::string differences = by_setting ? "successive differences within a setting" : "successive differences";
  prepared.noise = successive.sd;
  prepared.noise_dof = successive.dof;
  prepared.noise_source = differences + " (no repeated measurements)";
  const Spread across = spread(&Point::condition);
  if (across.dof >= 2 && across.sd < prepared.noise) {
    prepared.noise_source = fmt::format(
        "spread between repetitions of a condition reached from either side{}, hysteresis included (no condition "
        "repeats from one side; {}: {:.3g})",
        about, differences, prepared.noise);
    prepared.noise = across.sd;
    prepared.noise_dof = across.dof;
  }
}

// White measurement noise of a sampled signal from its second differences (robust to steps and to smooth motion):
// for white noise var(y[i+1] - 2 y[i] + y[i-1]) = 6 sigma^2; the median absolute value is 0.6745 of its sigma.
double second_difference_noise(const std::vector<double>& y) {
  std::vector<double> d;
  for (std::size_t i = 1; i + 1 < y.size(); ++i) d.push_back(std::abs(y[i + 1] - 2.0 * y[i] + y[i - 1]));
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  return d[d.size() / 2] / 0.6745 / std::sqrt(6.0);
}

// The measurement noise of a sampled signal from its spread about a quadratic fitted in each window of `window`
// samples (smooth motion removed), as the median over windows (a window holding a step is an outlier) corrected for
// the median's bias (Wilson-Hilferty: the median of chi^2_k / k is about (1 - 2/(9k))^3). Unlike second differences,
// which see only the noise that changes from one sample to the next, it sees coloured noise (a sensor's own filter,
// slow wander within the window) at nearly its full size; for white noise the two agree.
double windowed_noise(const std::vector<double>& y, std::size_t window) {
  std::vector<double> variances;
  for (std::size_t start = 0; start + window <= y.size(); start += window) {
    // Least squares of y against 1, x, x^2 with x centred in the window (normal equations: x is symmetric, so odd
    // moments vanish).
    double s0 = 0, s2 = 0, s4 = 0, t0 = 0, t1 = 0, t2 = 0;
    const double mid = 0.5 * static_cast<double>(window - 1);
    for (std::size_t k = 0; k < window; ++k) {
      const double x = static_cast<double>(k) - mid, v = y[start + k];
      s0 += 1;
      s2 += x * x;
      s4 += x * x * x * x;
      t0 += v;
      t1 += x * v;
      t2 += x * x * v;
    }
    const double c = (s0 * t2 - s2 * t0) / (s0 * s4 - s2 * s2), a = (t0 - c * s2) / s0, b = t1 / s2;
    double ss = 0.0;
    for (std::size_t k = 0; k < window; ++k) {
      const double x = static_cast<double>(k) - mid;
      ss += std::pow(y[start + k] - (a + b * x + c * x * x), 2);
    }
    variances.push_back(ss / static_cast<double>(window - 3));
  }
  if (variances.empty()) return 0.0;
  std::nth_element(variances.begin(), variances.begin() + static_cast<long>(variances.size() / 2), variances.end());
  const double dof = static_cast<double>(window - 3);
  return std::sqrt(variances[variances.size() / 2] / std::pow(1.0 - 2.0 / (9.0 * dof), 3));
}

// The least noise of an angle read with `resolution` [rad] steps: the quantisation's resolution / sqrt(12) [deg].
double quantisation_noise_deg(double resolution) { return rad_to_deg(resolution) / std::sqrt(12.0); }

// Raises an angle trial's noise to its sensor's quantisation noise, saying so.
void apply_resolution_floor(PreparedTrial& p) {
  const double floor = quantisation_noise_deg(p.trial->conventions.angle_resolution);
  if (p.unit == "deg" && p.noise < floor) {
    p.noise = floor;
    p.noise_source = fmt::format("the angle sensor's {:.4g} deg resolution (the estimate, {}, was smaller)",
                                 rad_to_deg(p.trial->conventions.angle_resolution), p.noise_source);
  }
}

PreparedTrial prepare_sweep(const Trial& trial) {
  PreparedTrial p{.trial = &trial, .name = trial.name, .unit = "N m"};
  std::map<int, std::vector<std::size_t>> by_muscle;
  for (std::size_t i = 0; i < trial.sweep.size(); ++i) by_muscle[trial.sweep[i].muscle].push_back(i);
  p.points.resize(trial.sweep.size());
  Ids<std::tuple<int, int, long, int>> groups;  // a held angle reached from either side is two conditions
  Ids<std::tuple<int, int, long>> conditions;   // ... of one condition, for the noise (estimate_noise)
  Ids<std::pair<int, int>> units;
  for (const auto& [muscle, rows] : by_muscle) {
    std::vector<double> angles, pressures_kpa;
    for (std::size_t i : rows) {
      angles.push_back(rad_to_deg(trial.sweep[i].angle));
      pressures_kpa.push_back(pa_to_kpa(trial.sweep[i].pressure));
    }
    const std::vector<int> cluster = set_angle_clusters(angles);
    const std::vector<int> level = clusters(pressures_kpa, kSweepLevelGapKpa);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const SweepPoint& s = trial.sweep[rows[k]];
      Point& point = p.points[rows[k]];
      point.measured = s.torque;
      point.angle_deg = angles[k];
      point.pressure_kpa = pressures_kpa[k];
      point.muscle = muscle;
      point.motion = s.motion;
      point.group = groups({muscle, cluster[k], std::lround(point.pressure_kpa), s.motion});
      // A reading less the same angle's at 0 kPa is 0 there by definition, in the log and in the model: no noise.
      const bool defined_zero = trial.conventions.torque.baseline_subtracted && s.pressure == 0.0;
      point.condition = defined_zero ? -1 : conditions({muscle, cluster[k], std::lround(point.pressure_kpa)});
      point.unit = units({muscle, cluster[k]});
      // Held out as a checkerboard: every other pressure level at each held angle, the other levels at the next
      // angle. Every held angle is a bootstrap unit with points in both parts (every other angle, as before, left
      // four units per muscle, one the end of the range, and fits that moved the angles in between untested).
      point.heldout = (cluster[k] + level[k]) % 2 == 1;
      point.repetition = s.repetition;
    }
  }
  // Settings in the log's order: a new one wherever the held angle or the repetition changes.
  int setting = -1;
  for (std::size_t i = 0; i < p.points.size(); ++i) {
    Point& point = p.points[i];
    const bool same = i > 0 && point.unit == p.points[i - 1].unit && point.repetition == p.points[i - 1].repetition;
    if (!same) ++setting;
    point.setting = point.condition < 0 ? -1 : setting;  // a reading defined as 0 has no noise
  }
  return p;
}

PreparedTrial prepare_rom(const Trial& trial) {
  PreparedTrial p{.trial = &trial, .name = trial.name, .unit = "deg"};
  int max_repetition = 0;
  for (const auto& r : trial.rom) max_repetition = std::max(max_repetition, r.repetition);
  Ids<std::pair<int, long>> groups;
  Ids<std::pair<int, int>> units;
  for (const RomPoint& r : trial.rom) {
    Point point{.measured = rad_to_deg(r.limit),
                .angle_deg = rad_to_deg(r.limit),
                .pressure_kpa = pa_to_kpa(r.pressure),
                .muscle = r.muscle,
                .repetition = r.repetition};
    point.group = groups({r.muscle, std::lround(point.pressure_kpa)});
    point.unit = units({r.muscle, r.repetition});
    // Repeated trials: hold out every other repetition; a single one: the extensor and radial muscles.
    point.heldout =
        max_repetition > 0 ? r.repetition % 2 == 1 : (r.muscle == sim::kExtensor || r.muscle == sim::kRadial);
    p.points.push_back(point);
  }
  return p;
}

PreparedTrial prepare_tensile(const Trial& trial) {
  PreparedTrial p{.trial = &trial, .name = trial.name, .unit = "N"};
  std::vector<double> pressures;
  for (const auto& t : trial.tensile) pressures.push_back(pa_to_kpa(t.pressure));
  const std::vector<int> level = clusters(pressures, 1.0);
  const int levels = level.empty() ? 0 : *std::max_element(level.begin(), level.end()) + 1;
  Ids<std::tuple<int, bool, long>> groups;
  for (std::size_t i = 0; i < trial.tensile.size(); ++i) {
    const TensilePoint& t = trial.tensile[i];
    const long bin = std::lround(t.contraction / 0.005);
    Point point{.measured = t.force,
                .pressure_kpa = pressures[i],
                .contraction = t.contraction,
                .motion = t.loading ? 1 : -1,
                .repetition = t.cycle};
    point.group = groups({level[i], t.loading, bin});
    // Several pressures: hold out every other pressure; one: every other contraction step.
    point.unit = levels > 1 ? level[i] : static_cast<int>(bin);
    point.heldout = point.unit % 2 == 1;
    p.points.push_back(point);
  }
  return p;
}

// A trajectory's angles (channels 0, 1) or, with `pressures`, its measured pressures (channel 2 + muscle).
PreparedTrial prepare_trajectory(const Trial& trial, bool pressures) {
  PreparedTrial p{.trial = &trial,
                  .name = pressures ? trial.name + " pressures" : trial.name,
                  .pressures = pressures,
                  .unit = pressures ? "kPa" : "deg"};
  const auto& s = trial.trajectory;
  const double t0 = s.front().t, t1 = s.back().t;
  p.training_end_s = t0 + 0.5 * (t1 - t0);  // the first half trains (a repeated task: split_by_repetition)
  const int channels = pressures ? 4 : 2;
  std::vector<std::vector<double>> y(static_cast<std::size_t>(channels));
  for (const auto& sample : s) {
    if (pressures) {
      for (std::size_t m = 0; m < 4; ++m) y[m].push_back((*sample.measured_kpa)[m]);
    } else {
      y[0].push_back(rad_to_deg(sample.fe));
      y[1].push_back(rad_to_deg(sample.ur));
    }
  }
  double noise2 = 0.0;
  bool coloured = false;  // the windowed estimate exceeded the second differences'
  for (int c = 0; c < channels; ++c) {
    const auto& yc = y[static_cast<std::size_t>(c)];
    const double white = second_difference_noise(yc), windowed = windowed_noise(yc, kNoiseWindow);
    coloured = coloured || windowed > white;
    noise2 += std::pow(std::max(white, windowed), 2) / channels;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::size_t a = i >= 3 ? i - 3 : 0, b = std::min(s.size() - 1, i + 3);
      const double rate = (yc[b] - yc[a]) / std::max(1e-9, s[b].t - s[a].t);
      const int channel = pressures ? 2 + c : c;
      Point point{.measured = yc[i], .channel = channel, .t_s = s[i].t};
      if (pressures) {
        point.pressure_kpa = yc[i];
        point.muscle = c;
        point.motion = rate > 5.0 ? 1 : (rate < -5.0 ? -1 : 0);  // [kPa/s] filling, venting
      } else {
        point.angle_deg = yc[i];
        point.motion = rate > 2.0 ? 1 : (rate < -2.0 ? -1 : 0);  // [deg/s]
      }
      point.group = channel * 1000000 + static_cast<int>((s[i].t - t0) / kTrajectoryGroup);
      point.unit = static_cast<int>((s[i].t - t0) / kTrajectoryUnit);
      point.heldout = s[i].t >= p.training_end_s;
      p.points.push_back(point);
    }
  }
  p.noise = std::sqrt(noise2);
  p.noise_dof = static_cast<int>(p.points.size());
  const std::string what = pressures ? "the measured pressures" : "the measured angles";
  p.noise_source = coloured ? fmt::format("spread of {} about a quadratic in {}-sample windows", what, kNoiseWindow)
                            : fmt::format("second differences of {} (white sensor noise)", what);
  if (pressures && p.noise < kPressureResolutionKpa / std::sqrt(12.0)) {
    p.noise = kPressureResolutionKpa / std::sqrt(12.0);
    p.noise_source = fmt::format("the logged pressures' {} kPa resolution (their second differences are smaller)",
                                 kPressureResolutionKpa);
  }
  return p;
}

// The logged commands as the regulators receive them, `dead_time` late, averaged over each simulation step. A
// command reaches the regulators at its row's time plus the dead time, which in general falls within a step; the
// regulators integrate their input, so the step's mean command is their input to first order in the step, and the
// replay is continuous in the dead time (applied at the next step instead, a fit of the dead time met a staircase of
// one step's width: a true 40 ms came out 47 ms, docs/diagnosis.md). Where every change falls on a step's start (no
// dead time, rows on the step grid) it is exactly the row in force.
class StepCommands {
 public:
  // `before`: the command the regulators hold before the first row reaches them.
  StepCommands(const std::vector<TrajectorySample>& samples, double dead_time, const control::Pressures& before)
      : samples_(samples), dead_time_(dead_time), in_force_(before) {}
  // The mean command over the step [from, to) of the log's time, or nothing if it is the previous step's command.
  std::optional<control::Pressures> over(double from, double to) {
    bool changed = mixed_;
    while (next_ < samples_.size() && arrival(next_) <= from + kSnap) {  // reached by the step's start
      in_force_ = samples_[next_++].command_kpa;
      changed = true;
    }
    mixed_ = false;
    if (next_ == samples_.size() || arrival(next_) >= to - kSnap) {
      return changed ? std::optional(in_force_) : std::nullopt;
    }
    // Rows reach the regulators within the step: each command in force for its share of it.
    control::Pressures mean{};
    double at = from;
    while (at < to) {
      const double until = next_ < samples_.size() && arrival(next_) < to - kSnap ? arrival(next_) : to;
      for (std::size_t m = 0; m < 4; ++m) mean[m] += in_force_[m] * (until - at) / (to - from);
      if (until < to) in_force_ = samples_[next_++].command_kpa;
      at = until;
    }
    mixed_ = true;
    return mean;
  }

 private:
  // Changes closer than this to a step's edge count as at it (the log's times are not exact multiples of the step).
  static constexpr double kSnap = 1e-9;  // [s]
  double arrival(std::size_t row) const { return samples_[row].t + dead_time_; }
  const std::vector<TrajectorySample>& samples_;
  double dead_time_;
  control::Pressures in_force_;
  std::size_t next_ = 0;  // rows that have reached the regulators
  bool mixed_ = false;    // the last step's command was a mean
};

// `series`, sampled every `dt` from t = 0, at time `t`: linear between samples (a sample itself on the grid), held
// beyond its ends.
double sampled_at(const std::vector<double>& series, double dt, double t) {
  const double k = std::clamp(t / dt, 0.0, static_cast<double>(series.size() - 1));
  const auto below = std::min(series.size() - 1, static_cast<std::size_t>(k));
  const std::size_t above = std::min(series.size() - 1, below + 1);
  const double w = k - static_cast<double>(below);
  return w < 1e-9 ? series[below] : (1.0 - w) * series[below] + w * series[above];
}

// What a trajectory's replay depends on besides the model: the trial and the conventions that change how it is run
// (the start, the gravity).
std::string trial_key(const Trial& trial) {
  return fmt::format("{}|{}|{}|{}", trial.name, trial.file, trial.conventions.angles_zeroed_at_start,
                     static_cast<int>(trial.conventions.posture));
}

std::string cache_key(const Trial& trial, const ModelVariant& variant, double horizon, double timestep) {
  return fmt::format("{}|{}|{}|{}|{}", trial_key(trial), sim::device_to_json(variant.device_for(trial)),
                     variant.regulator_dead_time, horizon, timestep);
}

// Tells one set of drive readings from another in a cache key.
std::uint64_t fingerprint(const std::vector<control::Pressures>& readings) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the readings' bits
  for (const auto& r : readings) {
    for (double v : r) {
      h ^= std::bit_cast<std::uint64_t>(v);
      h *= 1099511628211ull;
    }
  }
  return h;
}

// The key of angles replayed from measured pressures: the regulators' response and dead time do not reach them, the
// monitors' calibration does (it turns a reading into a pressure), so a fit of the regulator reuses one replay.
std::string measured_drive_key(const Trial& trial, const ModelVariant& variant, double horizon,
                               const std::vector<control::Pressures>& drive, double timestep) {
  sim::DeviceDescription device = variant.device_for(trial);
  const double max_pressure = device.regulator.max_pressure;
  device.regulator = sim::Regulator{.max_pressure = max_pressure};
  return fmt::format("measured|{}|{}|{}|{}|{}|{}|{}", trial_key(trial), sim::device_to_json(device),
                     fmt::join(variant.monitor_gain, ","), fmt::join(variant.monitor_offset, ","), horizon,
                     fingerprint(drive), timestep);
}

// [s] the Gaussian kernel's standard deviation that smooths the measured readings' difference from the nominal's
// (drive_readings): its response is 0.17 at 3 Hz, the paper device's wrist resonance, and 0.93 at 0.6 Hz; the
// independent device's slowest second-order regulator rings at 0.6 Hz.
constexpr double kDriveSmoothing = 0.1;

// `values` (one per row) smoothed by a Gaussian kernel of kDriveSmoothing in time (rows need not be evenly spaced),
// cut at 3 sigma.
std::vector<control::Pressures> smoothed(const std::vector<TrajectorySample>& samples,
                                         const std::vector<control::Pressures>& values) {
  const std::size_t n = samples.size();
  std::vector<control::Pressures> out(n);
  std::size_t from = 0, to = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (samples[from].t < samples[i].t - 3.0 * kDriveSmoothing) ++from;
    while (to < n && samples[to].t <= samples[i].t + 3.0 * kDriveSmoothing) ++to;
    control::Pressures sum{};
    double weights = 0.0;
    for (std::size_t j = from; j < to; ++j) {
      const double weight = std::exp(-0.5 * std::pow((samples[j].t - samples[i].t) / kDriveSmoothing, 2));
      for (std::size_t m = 0; m < 4; ++m) sum[m] += weight * values[j][m];
      weights += weight;
    }
    for (std::size_t m = 0; m < 4; ++m) out[i][m] = sum[m] / weights;
  }
  return out;
}

// A trajectory's measured pressures as the muscles had them: the readings that drive them turned back into pressures
// through the variant's calibration (a reading is gain x pressure + offset), linear between rows, held before the
// first and after the last, within the regulators' range. Asked at increasing times.
class MeasuredPressures {
 public:
  MeasuredPressures(const std::vector<TrajectorySample>& samples, const std::vector<control::Pressures>& readings,
                    const ModelVariant& variant, double max_kpa)
      : samples_(samples), readings_(readings), variant_(variant), max_kpa_(max_kpa) {}
  control::Pressures at(double t) {
    while (next_ < samples_.size() && samples_[next_].t <= t) ++next_;
    const std::size_t above = std::min(next_, samples_.size() - 1), below = next_ == 0 ? 0 : next_ - 1;
    const double span = samples_[above].t - samples_[below].t;
    const double w = above == below || span <= 0.0 ? 0.0 : std::clamp((t - samples_[below].t) / span, 0.0, 1.0);
    control::Pressures out{};
    for (std::size_t m = 0; m < 4; ++m) {
      const double reading = (1.0 - w) * readings_[below][m] + w * readings_[above][m];
      const double kpa = (reading - pa_to_kpa(variant_.monitor_offset[m])) / variant_.monitor_gain[m];
      out[m] = std::clamp(kpa, 0.0, max_kpa_);
    }
    return out;
  }

 private:
  const std::vector<TrajectorySample>& samples_;
  const std::vector<control::Pressures>& readings_;
  const ModelVariant& variant_;
  double max_kpa_;
  std::size_t next_ = 0;  // the first row after the last time asked
};

}  // namespace

bool acts_on(const EffectSpec& effect, const PreparedTrial& trial) {
  if (!effect.acts_on_kind(trial.trial->kind)) return false;
  // The measured pressures are compared with the regulators' alone, which do not feel the muscles or the wrist: only
  // an effect that acts through the regulators changes them.
  if (trial.pressures) return effect.through_regulators_only;
  // A sweep's sensor weighs the relaxed wrist only where its convention says so: the muscle's torque alone, or the
  // reading less its 0 kPa baseline, does not move with the wrist's stiffness (conventions.h, TorqueIncludes).
  if (effect.id == EffectId::kPassiveWrist && trial.trial->kind == TrialKind::kTorqueSweep)
    return trial.trial->conventions.torque.weighs_passive_wrist();
  // A settled limit does not depend on the regulators: they change a range of motion only through the pressure left
  // when its angles were zeroed (predict_rom).
  if (effect.through_regulators_only && trial.trial->kind == TrialKind::kRangeOfMotion)
    return trial.trial->conventions.angles_zeroed_at_start;
  return !(trial.angles_from_measured_pressures && effect.through_regulators_only);
}

std::vector<double> residuals_of(const PreparedTrial& trial, const std::vector<double>& predicted) {
  std::vector<double> residuals(predicted.size());
  for (std::size_t i = 0; i < predicted.size(); ++i) residuals[i] = trial.points[i].measured - predicted[i];
  return residuals;
}

namespace {

// The noise the measured pressures carry into angles replayed from them, added to the angle trial's own: the
// pressures' noise (`pressure_noise` [kPa] per reading, white) smoothed as the drive is, propagated through one
// replay of the nominal, and its difference from the nominal's angles taken as a second noise of the trial, with its
// 1 s block means (it is slow: the wrist low-passes it) in the group test's variance. Without it a correct model
// was called wrong: on the paper's device 0.31 kPa of pressure noise moved the replayed angles 0.12 deg RMS beside
// the IMU's 0.25 deg (p = 2e-8 for the nominal), the wrist being soft enough that a tenth of a kPa turns it a
// degree's fraction.
void add_drive_noise(PreparedTrial& p, double pressure_noise, ReplayEngine& engine, const ModelVariant& nominal) {
  const auto& samples = p.trial->trajectory;
  std::mt19937_64 rng(20261126);  // one fixed realisation: the same data give the same noise
  std::normal_distribution<double> normal(0.0, pressure_noise);
  std::vector<control::Pressures> noise(samples.size());
  for (auto& row : noise) {
    for (double& v : row) v = normal(rng);
  }
  const std::vector<control::Pressures> smooth = smoothed(samples, noise);
  PreparedTrial perturbed = p;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    for (std::size_t m = 0; m < 4; ++m) perturbed.drive_readings[i][m] += smooth[i][m];
  }
  const std::vector<double> base = engine.predict(p, nominal, false), moved = engine.predict(perturbed, nominal, false);
  double ss = 0.0;
  std::map<int, std::pair<double, int>> blocks;
  for (std::size_t i = 0; i < base.size(); ++i) {
    const double d = moved[i] - base[i];
    ss += d * d;
    auto& b = blocks[p.points[i].group];
    b.first += d;
    ++b.second;
  }
  const double drive2 = ss / static_cast<double>(base.size());
  if (!(drive2 > 0.0) || blocks.empty()) return;
  double block_mean2 = 0.0, per_block = 0.0;
  for (const auto& [group, b] : blocks) {
    block_mean2 += std::pow(b.first / b.second, 2) / static_cast<double>(blocks.size());
    per_block += static_cast<double>(b.second) / static_cast<double>(blocks.size());
  }
  const double own2 = p.noise * p.noise, total2 = own2 + drive2;
  // A block mean's variance: the own noise's (inflated as it was) plus the drive's.
  p.group_inflation = std::max(1.0, (own2 * p.group_inflation / per_block + block_mean2) * per_block / total2);
  p.noise_source = fmt::format(
      "{}, and {:.3g} {} that the measured pressures' {:.3g} kPa of noise carries into the "
      "angles replayed from them",
      p.noise_source, std::sqrt(drive2), p.unit, pressure_noise);
  p.noise = std::sqrt(total2);
}

// A repeated trajectory task's repetitions alternate whole between the training and the held-out part (the first,
// third, ... train), so that both parts reach every state the task does. Split in time instead (the first half of each
// trial trains), the held-out half of a 12 s ellipse was the half that reaches large deviation: the tolerances and
// effects were fitted where the model's error is small and judged where it is large (the independent device's nominal,
// seed 45: 2-3 deg in deviation beyond 15 deg, all after 6 s, which no fit within the tolerances had seen). A trial of
// no repeated task keeps its time split (prepare_trajectory).
void split_by_repetition(std::vector<PreparedTrial>& prepared, const std::vector<std::vector<std::size_t>>& sets) {
  for (const auto& set : sets) {
    for (std::size_t k = 0; k < set.size(); ++k) {
      PreparedTrial& p = prepared[set[k]];
      const bool training = k % 2 == 0;
      const auto& samples = p.trial->trajectory;
      p.training_end_s = training ? samples.back().t : samples.front().t;
      for (Point& point : p.points) point.heldout = !training;
    }
  }
}

}  // namespace

std::vector<PreparedTrial> prepare(const RealData& data, ReplayEngine& engine, const ModelVariant& nominal) {
  std::vector<PreparedTrial> prepared;
  for (const Trial& trial : data.trials) {
    PreparedTrial p;
    switch (trial.kind) {
      case TrialKind::kTorqueSweep:
        p = prepare_sweep(trial);
        break;
      case TrialKind::kRangeOfMotion:
        p = prepare_rom(trial);
        break;
      case TrialKind::kTensile:
        p = prepare_tensile(trial);
        break;
      case TrialKind::kTrajectory:
        p = prepare_trajectory(trial, false);
        p.angles_from_measured_pressures = engine.angles_from_measured_pressures(trial);
        if (p.angles_from_measured_pressures) p.drive_readings = engine.drive_readings(trial, nominal);
        break;
    }
    if (trial.kind != TrialKind::kTrajectory) {
      const std::vector<double> residuals = residuals_of(p, engine.predict(p, nominal, false));
      estimate_noise(p, residuals);
      if (trial.kind == TrialKind::kTorqueSweep) estimate_setting_scatter(p, residuals);
    }
    apply_resolution_floor(p);
    if (trial.kind == TrialKind::kTrajectory && trial.trajectory.front().measured_kpa) {
      PreparedTrial pressures = prepare_trajectory(trial, true);
      if (p.angles_from_measured_pressures) add_drive_noise(p, pressures.noise, engine, nominal);
      prepared.push_back(std::move(p));
      prepared.push_back(std::move(pressures));
    } else {
      prepared.push_back(std::move(p));
    }
  }
  // Repeated trajectories: their noise from the spread across repetitions (the nominal replays are cached for the
  // diagnosis that follows).
  const auto sets = repeat_sets(prepared);
  split_by_repetition(prepared, sets);
  if (!sets.empty()) {
    std::vector<std::vector<double>> residuals(prepared.size());
    for (const auto& set : sets) {
      for (std::size_t t : set) residuals[t] = residuals_of(prepared[t], engine.predict(prepared[t], nominal, false));
    }
    apply_repeat_noise(prepared, sets, residuals);
  }
  return prepared;
}

void ReplayEngine::check_replayable(const Trial& trial, const ModelVariant& variant) const {
  const double max_kpa = pa_to_kpa(variant.device_for(trial).regulator.max_pressure);
  const auto check = [&](double kpa) {
    if (kpa > max_kpa + 1e-9) {
      throw std::runtime_error(
          fmt::format("{}: {} kPa is beyond the model's regulators ({} kPa)", trial.name, kpa, max_kpa));
    }
  };
  for (const auto& s : trial.sweep) check(pa_to_kpa(s.pressure));
  for (const auto& r : trial.rom) check(pa_to_kpa(r.pressure));
  for (const auto& s : trial.trajectory) {
    for (double kpa : s.command_kpa) check(kpa);
  }
  if (trial.kind == TrialKind::kTrajectory && trial.trajectory.back().t > 3600.0) {
    throw std::runtime_error(
        fmt::format("{}: {} s is longer than the hour a replay is allowed", trial.name, trial.trajectory.back().t));
  }
}

std::shared_ptr<const ReplayEngine::Simulated> ReplayEngine::cached(
    const std::string& key, const std::function<std::shared_ptr<const Simulated>()>& compute) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = cache_.find(key); it != cache_.end()) {
      ++stats_.cache_hits;
      return it->second;
    }
  }
  std::shared_ptr<const Simulated> result = compute();  // outside the lock: replays run in parallel
  std::lock_guard lock(mutex_);
  if (cache_.size() >= 32) cache_.erase(cache_.begin());
  cache_.emplace(key, result);
  return result;
}

sim::Model ReplayEngine::load_model(const sim::DeviceDescription& device, const Trial& trial, double timestep) const {
  sim::ModelOptions options;
  options.timestep = timestep;
  options.anatomy = false;  // drawing only: it moves nothing, and compiling its meshes was 90 % of a model's load
  const auto axis = gravity_axis(trial.conventions.posture);
  options.gravity = axis ? sim::kStandardGravity : 0.0;
  if (axis) options.gravity_axis = *axis;
  return sim::Model::FromXml(sim::build_model_xml(device, options), plugins_, trial.name);
}

bool ReplayEngine::angles_from_measured_pressures(const Trial& trial) const {
  return pressure_source_ == PressureSource::kMeasuredWhereLogged && trial.kind == TrialKind::kTrajectory &&
         !trial.trajectory.empty() && trial.trajectory.front().measured_kpa.has_value();
}

bool ReplayEngine::depends_on_step(const PreparedTrial& prepared) const {
  const Trial& trial = *prepared.trial;
  if (trial.kind == TrialKind::kRangeOfMotion) return true;
  return trial.kind == TrialKind::kTrajectory && !(prepared.pressures && angles_from_measured_pressures(trial));
}

ReplayStats ReplayEngine::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::shared_ptr<const ReplayEngine::Simulated> ReplayEngine::simulate(const Trial& trial, const ModelVariant& variant,
                                                                      double horizon,
                                                                      const std::vector<control::Pressures>* drive,
                                                                      double timestep) {
  const bool measured = drive != nullptr;
  if (measured && drive->size() != trial.trajectory.size()) {
    throw std::logic_error(
        fmt::format("{}: {} drive readings for {} rows", trial.name, drive->size(), trial.trajectory.size()));
  }
  const std::string key = measured ? measured_drive_key(trial, variant, horizon, *drive, timestep)
                                   : cache_key(trial, variant, horizon, timestep);
  return cached(key, [&] {
    const auto started = std::chrono::steady_clock::now();
    const sim::DeviceDescription& device = variant.device_for(trial);
    const sim::Model model = load_model(device, trial, timestep);
    sim::WristSim wrist(model);
    wrist.reset();
    const auto& samples = trial.trajectory;
    std::optional<MeasuredPressures> pressures;
    if (measured) pressures.emplace(samples, *drive, variant, pa_to_kpa(device.regulator.max_pressure));
    if (trial.conventions.angles_zeroed_at_start) {
      if (measured) {
        wrist.set_regulated_pressures_kpa(pressures->at(samples.front().t));
      } else {
        wrist.command_pressures_kpa(samples.front().command_kpa);
      }
      wrist.run(kPreSettle);
    }
    const double start = wrist.time();  // the log's t = 0
    auto result = std::make_shared<Simulated>();
    result->dt = model->opt.timestep;
    const auto steps = static_cast<std::size_t>(std::ceil(horizon / result->dt)) + 1;
    result->fe.reserve(steps);
    result->ur.reserve(steps);
    for (auto& p : result->pressure_kpa) p.reserve(steps);
    StepCommands commands(
        samples, variant.regulator_dead_time,
        trial.conventions.angles_zeroed_at_start ? samples.front().command_kpa : control::Pressures{});
    for (std::size_t k = 0; k < steps; ++k) {
      const double t = wrist.time() - start;
      if (measured) {
        // A step's force is the pressure at its start (MuJoCo's Euler step): the measured pressure there.
        wrist.set_regulated_pressures_kpa(pressures->at(t));
      } else if (const auto command = commands.over(t, t + result->dt)) {
        wrist.command_pressures_kpa(*command);
      }
      result->fe.push_back(wrist.angle(physics::WristAxis::kFlexionExtension));
      result->ur.push_back(wrist.angle(physics::WristAxis::kUlnarRadial));
      for (std::size_t m = 0; m < 4; ++m) {
        result->pressure_kpa[m].push_back(wrist.regulated_pressure_kpa(static_cast<sim::MuscleIndex>(m)));
      }
      wrist.run(result->dt);
      if (!std::isfinite(result->fe.back()) || !std::isfinite(result->ur.back())) {
        throw std::runtime_error(fmt::format("{}: the replay diverged at t = {} s", trial.name, wrist.time() - start));
      }
    }
    std::lock_guard lock(mutex_);
    ++stats_.trajectories;
    stats_.trajectory_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    stats_.trajectory_sim_s += horizon;
    return std::shared_ptr<const Simulated>(std::move(result));
  });
}

namespace {

// One step of the plugin's regulators (plugins/fpam: FpamActuator::PressureRate, SecondOrderStep) as MuJoCo 2.2.2
// advances them: an Euler step of the activation with the rate at the step's start, the command clamped to the
// regulator's range; the second order's rates make that step exact (physics::regulator_step).
void step_regulators(const physics::RegulatorResponse& response, double max_kpa, double dt,
                     const control::Pressures& command, std::array<physics::RegulatedPressure, 4>& state) {
  for (std::size_t m = 0; m < 4; ++m) {
    const double u = std::clamp(command[m], 0.0, max_kpa);
    if (response.second_order()) {
      state[m] = physics::regulator_step(response, state[m], u, dt);
    } else {
      state[m].pressure += dt * physics::pressure_rate(response, u, state[m].pressure);
    }
  }
}

}  // namespace

ReplayEngine::RegulatorStates ReplayEngine::regulator_start(const Trial& trial, const ModelVariant& variant) const {
  RegulatorStates state{};
  if (!trial.conventions.angles_zeroed_at_start) return state;
  const sim::DeviceDescription& device = variant.device_for(trial);
  const physics::RegulatorResponse response = device.regulator.response();
  const double max_kpa = pa_to_kpa(device.regulator.max_pressure), dt = steps_.trajectory;
  // As the wrist's pre-settling: whole steps until kPreSettle (WristSim::run's rounding).
  for (double t = 0.0; t < kPreSettle - 0.5 * dt; t += dt) {
    step_regulators(response, max_kpa, dt, trial.trajectory.front().command_kpa, state);
  }
  return state;
}

// replay_test checks it against the MuJoCo replay's pressures.
ReplayEngine::Simulated ReplayEngine::replay_regulators(const Trial& trial, const ModelVariant& variant, double horizon,
                                                        const RegulatorStates& start,
                                                        const RegulatorStates* at_first_row,
                                                        RegulatorStates* model_at_first_row) const {
  const sim::DeviceDescription& device = variant.device_for(trial);
  const physics::RegulatorResponse response = device.regulator.response();
  const double max_kpa = pa_to_kpa(device.regulator.max_pressure), dt = steps_.trajectory;
  RegulatorStates state = start;
  const auto& samples = trial.trajectory;
  const bool zeroed = trial.conventions.angles_zeroed_at_start;
  Simulated result;
  result.dt = dt;
  const auto steps = static_cast<std::size_t>(std::ceil(horizon / dt)) + 1;
  // The last step at or before the first row: the rows from it on lie between that step and later ones.
  const auto first_row_step = static_cast<std::size_t>(std::floor(samples.front().t / dt + 1e-9));
  StepCommands commands(samples, variant.regulator_dead_time,
                        zeroed ? samples.front().command_kpa : control::Pressures{});
  control::Pressures command = zeroed ? samples.front().command_kpa : control::Pressures{};
  for (std::size_t k = 0; k < steps; ++k) {
    const double t = static_cast<double>(k) * dt;
    if (const auto changed = commands.over(t, t + dt)) command = *changed;
    if (k == first_row_step) {
      if (model_at_first_row != nullptr) *model_at_first_row = state;
      if (at_first_row != nullptr) state = *at_first_row;
    }
    for (std::size_t m = 0; m < 4; ++m) result.pressure_kpa[m].push_back(state[m].pressure);
    step_regulators(response, max_kpa, dt, command, state);
  }
  return result;
}

// A trajectory's log need not begin with the regulators settled: the independent rig's trials begin 0.3-1 s after the
// first pressures were commanded, and a regulator still ringing then differs from the model's settled start for its
// whole settling time (seed 51's second_order_response, natural frequency 6.7 rad/s: with its start the catalogue's
// second-order form, fitted alone to the step trials' pressures, leaves 0.62 kPa rms, 0.19 kPa from the first second
// on, against 0.16 kPa of noise; its fit in the diagnosis took a 118 ms dead time and left 2.5-3.4 noise units). The
// regulators' state at the first row is a nuisance of the trial, as the angles' origin is (add_zeroing_offsets):
// fitted per muscle to the measured pressures of the first kWindow (least squares, from the training rows where the
// trial has any; a repetition held out whole fits its own from its first rows, 2 % of them), with the model's own
// response to a pressure and, second order, a rate moved at the first row: one Gauss-Newton step, exact where the
// response is linear in the state (no vent time constant that the moved response switches to). The state is moved at
// the first row's step, not at t = 0: a log that begins seconds in would otherwise ask a start the regulators forgot
// long before, and a pressure clamped to the regulator's range there.
ReplayEngine::RegulatorStates ReplayEngine::measured_regulator_start(const PreparedTrial& prepared,
                                                                     const ModelVariant& variant) const {
  // [s] 18 rows at the paper's 14 ms loop: a level and a slope well fixed against 0.1-0.2 kPa of noise, short against
  // the settling the regulator's own dynamics (what regulator_lag fits) shape.
  constexpr double kWindow = 0.25;
  constexpr double kPressureStep = 1.0;  // [kPa]
  constexpr double kRateStep = 10.0;     // [kPa/s]
  const Trial& trial = *prepared.trial;
  const sim::DeviceDescription& device = variant.device_for(trial);
  const bool second_order = device.regulator.response().second_order();
  const RegulatorStates settled = regulator_start(trial, variant);
  const double t0 = trial.trajectory.front().t;
  const double horizon = std::min(trial.trajectory.back().t, t0 + kWindow);
  RegulatorStates start{};  // the model's state at the first row
  std::vector<Simulated> runs{replay_regulators(trial, variant, horizon, settled, nullptr, &start)};
  std::vector<RegulatorStates> moved(second_order ? 2 : 1, start);
  for (auto& s : moved[0]) s.pressure += kPressureStep;
  if (second_order) {
    for (auto& s : moved[1]) s.rate += kRateStep;
  }
  for (const RegulatorStates& s : moved) runs.push_back(replay_regulators(trial, variant, horizon, settled, &s));
  const bool any_training =
      std::any_of(prepared.points.begin(), prepared.points.end(), [](const Point& p) { return !p.heldout; });
  RegulatorStates fitted = start;
  for (std::size_t m = 0; m < 4; ++m) {
    const auto at = [&](std::size_t run, double t) { return sampled_at(runs[run].pressure_kpa[m], runs[run].dt, t); };
    const double gain = variant.monitor_gain[m];
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    for (const Point& point : prepared.points) {
      if (point.channel != static_cast<int>(2 + m) || (point.heldout && any_training) || point.t_s > t0 + kWindow)
        continue;
      const double base = at(0, point.t_s);
      const Eigen::Vector2d slope(gain * (at(1, point.t_s) - base) / kPressureStep,
                                  second_order ? gain * (at(2, point.t_s) - base) / kRateStep : 0.0);
      normal += slope * slope.transpose();
      rhs += slope * (point.measured - gain * base - pa_to_kpa(variant.monitor_offset[m]));
    }
    if (!(normal(0, 0) > 0.0)) continue;  // no measured pressure in the window
    // A rate the window hardly tells from the pressure (a fast second pole, gone by the first rows: correlation above
    // 0.9995) is left at the model's rather than fitted to the noise.
    const bool rate_fitted = second_order && normal.determinant() > 1e-3 * normal(0, 0) * normal(1, 1);
    Eigen::Vector2d step =
        rate_fitted ? Eigen::Vector2d(normal.ldlt().solve(rhs)) : Eigen::Vector2d(rhs(0) / normal(0, 0), 0.0);
    if (!step.allFinite()) continue;
    const double pressure = std::clamp(start[m].pressure + step(0), 0.0, pa_to_kpa(device.regulator.max_pressure));
    if (rate_fitted && pressure != start[m].pressure + step(0)) {  // clamped: the rate refitted with it held
      step(0) = pressure - start[m].pressure;
      step(1) = (rhs(1) - normal(1, 0) * step(0)) / normal(1, 1);
    }
    fitted[m].pressure = pressure;
    fitted[m].rate = start[m].rate + step(1);
  }
  return fitted;
}

std::vector<control::Pressures> ReplayEngine::drive_readings(const Trial& trial, const ModelVariant& nominal) const {
  const auto& samples = trial.trajectory;
  const Simulated model = replay_regulators(trial, nominal, samples.back().t, regulator_start(trial, nominal));
  const std::size_t n = samples.size();
  std::vector<control::Pressures> model_reading(n), difference(n), out(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t m = 0; m < 4; ++m) {
      const double kpa = sampled_at(model.pressure_kpa[m], model.dt, samples[i].t);
      model_reading[i][m] = nominal.monitor_gain[m] * kpa + pa_to_kpa(nominal.monitor_offset[m]);
      difference[i][m] = (*samples[i].measured_kpa)[m] - model_reading[i][m];
    }
  }
  const std::vector<control::Pressures> smooth = smoothed(samples, difference);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t m = 0; m < 4; ++m) out[i][m] = model_reading[i][m] + smooth[i][m];
  }
  return out;
}

std::shared_ptr<const ReplayEngine::Simulated> ReplayEngine::settle(const Trial& trial,
                                                                    const sim::DeviceDescription& device,
                                                                    const std::vector<RomPose>& poses,
                                                                    double timestep) {
  // A settled limit does not depend on how fast the regulators reach their pressures (the regulators act on a range of
  // motion only through the pressure a slow vent leaves, which the poses carry): every pose settles under the
  // default response (sim::Regulator's, whatever the variant's or the placement's), so the time constants a
  // regulator_lag fit tries share one settle.
  sim::DeviceDescription settling = device;
  settling.regulator = sim::Regulator{.max_pressure = device.regulator.max_pressure};
  std::string key = fmt::format("rom|{}|{}|{}", trial_key(trial), sim::device_to_json(settling), timestep);
  for (const RomPose& pose : poses) key += fmt::format("|{}:{}", pose.read, fmt::join(pose.pressure_kpa, ","));
  return cached(key, [&] {
    // Each pose from the neutral wrist at rest, settled as the range-of-motion experiment does; the analytic statics
    // (sim::settled_angle) differ from the 3D tendon paths by up to a degree.
    const auto started = std::chrono::steady_clock::now();
    const sim::Model model = load_model(settling, trial, timestep);
    sim::WristSim wrist(model);
    auto result = std::make_shared<Simulated>();
    for (const RomPose& pose : poses) {
      const auto read = static_cast<sim::MuscleIndex>(pose.read);
      wrist.reset();
      wrist.command_pressures_kpa(pose.pressure_kpa);
      // Settled once the joint has been still (below 0.1 deg/s) for half a second after the first second, or
      // after kRomSettle.
      double still_since = 0.0;
      while (wrist.time() < kRomSettle - 1e-9 && (wrist.time() < 1.0 || wrist.time() - still_since < 0.5)) {
        wrist.run(0.05);
        if (std::abs(wrist.velocity(physics::axis_of(read))) > 1.7e-3) still_since = wrist.time();
      }
      result->fe.push_back(rad_to_deg(physics::direction_of(read) * wrist.angle(physics::axis_of(read))));
    }
    std::lock_guard lock(mutex_);
    stats_.settles += std::ssize(poses);
    stats_.settle_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return std::shared_ptr<const Simulated>(std::move(result));
  });
}

namespace {

// What a torque sweep's sensor reads at one point (conventions.h), positive in the muscle's own direction: the
// muscle's torque, plus the relaxed wrist's and the hand's weight's where the log says the reading includes them, or
// less the same angle's reading at 0 kPa.
// Hysteresis (physics/fpam_hysteresis.h) puts the muscle's pull on its lengthening branch (s = +1) where it was
// stretched into the held angle and on its shortening branch (s = -1) where it shortened into it (a held angle is
// reached over more than the transition length); the torque is the pull times its moment arm.
double sweep_reading(const physics::Muscle& muscle, const physics::WristModel& wrist, const SweepPoint& s,
                     const Conventions& c, const physics::FpamHysteresis& hysteresis) {
  const double direction = physics::direction_of(s.muscle);
  const double branch = -direction * s.motion;  // the muscle lengthens as the wrist moves against its own direction
  const auto torque_at = [&](double pressure) {
    const physics::MuscleState state = physics::muscle_state(muscle, direction * s.angle, pressure);
    if (!hysteresis.active() || branch == 0.0 || state.force <= 0.0) return state.torque;
    const double end_force = physics::pressure_end_force(pressure, muscle.fpam.at_pressure(pressure));
    return state.torque * physics::hysteretic_force(hysteresis, state.force, branch, end_force) / state.force;
  };
  const double torque = torque_at(s.pressure);
  if (c.torque.baseline_subtracted) return torque - torque_at(0.0);
  const physics::WristAxis axis = physics::axis_of(s.muscle);
  double other = 0.0;  // [N m] towards flexion / ulnar deviation
  if (c.torque.weighs_passive_wrist()) other += wrist.passive(axis, s.angle);
  // The hand's weight about the axis it turns, m g c cos(angle), largest with the hand level (wrist_statics.h).
  if (c.torque.hand_weight && gravity_axis(c.posture) == axis) other += wrist.hand_weight_moment * std::cos(s.angle);
  return torque + direction * other;
}

}  // namespace

std::vector<double> ReplayEngine::predict(const PreparedTrial& prepared, const ModelVariant& variant,
                                          bool training_only, Fidelity fidelity) {
  const Trial& trial = *prepared.trial;
  switch (trial.kind) {
    case TrialKind::kTorqueSweep:
      return predict_sweep(trial, variant.device_for(trial));
    case TrialKind::kRangeOfMotion:
      return predict_rom(trial, variant, fidelity);
    case TrialKind::kTensile:
      return predict_tensile(trial, variant.device_for(trial));
    case TrialKind::kTrajectory:
      return predict_trajectory(prepared, variant, training_only, fidelity);
  }
  return {};
}

// The tensile rig pulls the fPAM along the log's rows in their order: the hysteresis state (physics/fpam_hysteresis.h)
// follows the path from the first row's branch (the rig has cycled before), the fPAM on the rig taken as the exosuit's
// flexor (its L0 turns a step of contraction into one of length), so a branch turns over the transition length after
// each reversal instead of at once.
std::vector<double> ReplayEngine::predict_tensile(const Trial& trial, const sim::DeviceDescription& device) {
  const physics::FpamHysteresis& hysteresis = device.hysteresis;
  const double rest_length = device.muscles[physics::kFlexor].rest_length;
  std::vector<double> out;
  double state = 0.0, previous = 0.0;
  bool previous_loading = true;
  for (std::size_t i = 0; i < trial.tensile.size(); ++i) {
    const TensilePoint& t = trial.tensile[i];
    const double force = physics::fpam_force(device.fpam, t.pressure, t.contraction);
    if (!hysteresis.active()) {
      out.push_back(force);
      continue;
    }
    // A row that moves against its own direction flag (the next cycle, or rows not in the rig's order), or that
    // repeats the previous row's contraction under the other flag (a log binned by contraction records the reversal
    // on both branches), starts again from its flag's branch.
    const double lengthening = (previous - t.contraction) * rest_length;
    const bool along_the_path =
        i > 0 && (lengthening == 0.0 ? t.loading == previous_loading : (lengthening > 0.0) == t.loading);
    state = along_the_path ? physics::hysteresis_state_after(hysteresis, state, lengthening) : (t.loading ? 1.0 : -1.0);
    previous = t.contraction;
    previous_loading = t.loading;
    out.push_back(physics::hysteretic_force(
        hysteresis, force, state, physics::pressure_end_force(t.pressure, device.fpam.at_pressure(t.pressure))));
  }
  return out;
}

std::vector<double> ReplayEngine::predict_sweep(const Trial& trial, const sim::DeviceDescription& device) const {
  std::array<std::optional<physics::Muscle>, 4> muscles;
  const physics::WristModel wrist = sim::wrist_model(device);
  std::vector<double> out;
  for (const SweepPoint& s : trial.sweep) {
    if (!muscles[s.muscle]) muscles[s.muscle] = device.muscle(s.muscle);
    out.push_back(sweep_reading(*muscles[s.muscle], wrist, s, trial.conventions, device.hysteresis));
  }
  return out;
}

// The poses a range-of-motion row is read from: the limit with its muscle at its pressure, and (angles zeroed) the
// zero with it at rest. Where the angles were zeroed before each condition and the previous row's muscle had not
// vented fully (ModelVariant::rom_residual_fraction, r: a regulator venting slowly for the protocol's pause), the zero
// is taken with that muscle still at r times its pressure, and the limit read with it at r^2 times (as far again into
// the vent: a hold as long as the pause, which the logs do not record). The rows are taken in the order they were
// measured; the first starts from rest.
std::pair<ReplayEngine::RomPose, ReplayEngine::RomPose> rom_poses(const Trial& trial, std::size_t row,
                                                                  double residual_fraction) {
  const RomPoint& r = trial.rom[row];
  ReplayEngine::RomPose limit{.read = r.muscle}, zero{.read = r.muscle};
  limit.pressure_kpa[static_cast<std::size_t>(r.muscle)] = pa_to_kpa(r.pressure);
  if (row > 0 && residual_fraction > 0.0 && trial.conventions.angles_zeroed_at_start) {
    const RomPoint& previous = trial.rom[row - 1];
    const auto m = static_cast<std::size_t>(previous.muscle);
    zero.pressure_kpa[m] = residual_fraction * pa_to_kpa(previous.pressure);
    if (previous.muscle != r.muscle) limit.pressure_kpa[m] = residual_fraction * zero.pressure_kpa[m];
  }
  return {limit, zero};
}

std::vector<double> ReplayEngine::predict_rom(const Trial& trial, const ModelVariant& variant, Fidelity fidelity) {
  // The same pose settles alike: one simulation per pose, in the order of the map. Angles zeroed at the start are
  // read from where the wrist rests at 0 kPa (under the hand's weight, if any), or with the previous condition's
  // muscle not yet vented (rom_poses).
  const bool zeroed = trial.conventions.angles_zeroed_at_start;
  const double residual = variant.rom_residual_fraction;
  std::vector<std::pair<RomPose, RomPose>> rows;  // each row's limit and zero
  std::map<RomPose, double> settled;
  for (std::size_t i = 0; i < trial.rom.size(); ++i) {
    const auto& [limit, zero] = rows.emplace_back(rom_poses(trial, i, residual));
    settled.try_emplace(limit, 0.0);
    if (zeroed) settled.try_emplace(zero, 0.0);
  }
  std::vector<RomPose> poses;
  for (const auto& [pose, angle] : settled) poses.push_back(pose);
  const auto simulated =
      settle(trial, variant.device_for(trial), poses, fidelity == Fidelity::kCoarse ? steps_.coarse : steps_.settle);
  std::size_t k = 0;
  for (auto& [pose, angle] : settled) angle = simulated->fe[k++];
  std::vector<double> out;
  for (const auto& [limit, zero] : rows) out.push_back(settled.at(limit) - (zeroed ? settled.at(zero) : 0.0));
  return out;
}

namespace {

// Angles zeroed at a trial's start read 0 wherever the wrist was then, and a real trial need not start at rest (the
// hand set down near it, the first pressures filling, the sensors zeroed a moment later): the model, settled under
// the first command, then reads its angles from another origin, and the whole trial is off by that difference after
// the start's transient (on the independent device's second ellipse trial, 1.8 deg throughout in ulnar deviation,
// against 0.06 deg for the first). The origin is a nuisance, fitted per trial and angle (least squares: the mean of
// the residual), from the training rows after the first second, so that the held-out half does not inform it.
void add_zeroing_offsets(const PreparedTrial& prepared, std::vector<double>& predicted) {
  constexpr double kStartTransient = 1.0;  // [s] the wrist's own response settles in well under this (0.2-0.5 s)
  const double t0 = prepared.trial->trajectory.front().t;
  // A repetition held out whole (split_by_repetition) has no training rows: its own origin from all of them.
  const bool any_training =
      std::any_of(prepared.points.begin(), prepared.points.end(), [](const Point& p) { return !p.heldout; });
  for (const int channel : {0, 1}) {
    double sum = 0.0, late_sum = 0.0;
    std::size_t count = 0, late = 0;
    for (std::size_t i = 0; i < prepared.points.size(); ++i) {
      const Point& point = prepared.points[i];
      if (point.channel != channel || (point.heldout && any_training) || !std::isfinite(predicted[i])) continue;
      const double residual = point.measured - predicted[i];
      sum += residual;
      ++count;
      if (point.t_s >= t0 + kStartTransient) late_sum += residual, ++late;
    }
    if (count == 0) continue;
    const double offset = late > 0 ? late_sum / static_cast<double>(late) : sum / static_cast<double>(count);
    for (std::size_t i = 0; i < prepared.points.size(); ++i) {
      if (prepared.points[i].channel == channel) predicted[i] += offset;
    }
  }
}

}  // namespace

std::vector<double> ReplayEngine::predict_trajectory(const PreparedTrial& prepared, const ModelVariant& variant,
                                                     bool training_only, Fidelity fidelity) {
  const Trial& trial = *prepared.trial;
  // A repetition held out whole (split_by_repetition): nothing to replay for the training part.
  if (training_only && prepared.training_end_s <= trial.trajectory.front().t)
    return std::vector<double>(prepared.points.size(), NAN);
  const double horizon = training_only ? prepared.training_end_s : trial.trajectory.back().t;
  // Measured pressures compared with the regulators alone where measured pressures drive the angles' replay (cheap:
  // at the fine step in either fidelity), from the state their first rows show.
  const auto regulators_alone = [&] {
    const RegulatorStates first_row = measured_regulator_start(prepared, variant);
    return std::make_shared<const Simulated>(
        replay_regulators(trial, variant, horizon, regulator_start(trial, variant), &first_row));
  };
  const auto simulated = prepared.pressures && angles_from_measured_pressures(trial)
                             ? regulators_alone()
                             : simulate(trial, variant, horizon,
                                        prepared.angles_from_measured_pressures ? &prepared.drive_readings : nullptr,
                                        fidelity == Fidelity::kCoarse ? steps_.coarse : steps_.trajectory);
  const double imu_period = sim::ImuModel{}.period_s;
  const std::size_t n = trial.trajectory.size();
  // `series` at time `t`, linear between the steps (a row's time is not always on the step's grid).
  const auto at = [&](const std::vector<double>& series, double t) { return sampled_at(series, simulated->dt, t); };
  // The reading the IMUs last sampled (every 10 ms) before `t`, `latency` late, of `series`.
  const auto imu_reading = [&](const std::vector<double>& series, double t) {
    return at(series, std::max(0.0, std::floor((t - variant.imu_latency) / imu_period + 1e-9) * imu_period));
  };
  // Zeroed angles read 0 at the first row: the replay's own angles then are subtracted.
  const bool zeroed = trial.conventions.angles_zeroed_at_start && !prepared.pressures;
  const double t0 = trial.trajectory.front().t;
  const double zero_fe = zeroed ? imu_reading(simulated->fe, t0) : 0.0;
  const double zero_ur = zeroed ? imu_reading(simulated->ur, t0) : 0.0;
  std::vector<double> out(prepared.points.size(), NAN);
  for (std::size_t i = 0; i < prepared.points.size(); ++i) {
    const Point& point = prepared.points[i];
    if (training_only && point.heldout) continue;
    const double t = trial.trajectory[i % n].t;
    if (prepared.pressures) {  // the regulator's monitor output, read with the row
      const auto m = static_cast<std::size_t>(point.channel - 2);
      out[i] = variant.monitor_gain[m] * at(simulated->pressure_kpa[m], t) + pa_to_kpa(variant.monitor_offset[m]);
      continue;
    }
    // The IMU pair's axes turned by imu_axis_roll about the forearm (effects.h) mix the two angles.
    const double fe = imu_reading(simulated->fe, t) - zero_fe, ur = imu_reading(simulated->ur, t) - zero_ur;
    const double c = std::cos(variant.imu_axis_roll), s = std::sin(variant.imu_axis_roll);
    out[i] = point.channel == 0 ? rad_to_deg(c * fe - s * ur + variant.imu_offset_fe)
                                : rad_to_deg(s * fe + c * ur + variant.imu_offset_ur);
  }
  if (zeroed) add_zeroing_offsets(prepared, out);
  return out;
}

}  // namespace softwrist::diagnosis
