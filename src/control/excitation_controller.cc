#include "control/excitation_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace softwrist::control {
namespace {

void check_segments(const std::vector<ExcitationSegment>& segments, double max_kpa) {
  if (segments.empty()) throw std::invalid_argument("the excitation routine is empty");
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const ExcitationSegment& s = segments[i];
    if (!(s.duration_s > 0.0) || !std::isfinite(s.duration_s)) {
      throw std::invalid_argument(fmt::format("excitation segment {}: its length must be > 0 s", i));
    }
    for (std::size_t m = 0; m < s.from_kpa.size(); ++m) {
      for (double p : {s.from_kpa[m], s.to_kpa[m]}) {
        if (!(p >= 0.0 && p <= max_kpa)) {
          throw std::invalid_argument(fmt::format("excitation segment {}: {} pressure {} kPa is outside 0..{} kPa", i,
                                                  kMuscleNames[m], p, max_kpa));
        }
      }
    }
  }
}

Pressures only(int muscle, double kpa) {
  Pressures p{};
  p[static_cast<std::size_t>(muscle)] = kpa;
  return p;
}

}  // namespace

std::vector<ExcitationSegment> excitation_routine(const ExcitationRoutineParameters& parameters, double max_kpa) {
  const ExcitationRoutineParameters& q = parameters;
  if (q.step_levels_kpa.empty()) throw std::invalid_argument("the excitation routine needs at least one step level");
  const double top = *std::max_element(q.step_levels_kpa.begin(), q.step_levels_kpa.end());
  if (!(q.edge_rate_kpa_s > 0.0)) throw std::invalid_argument("the excitation's edge rate must be > 0 kPa/s");
  std::vector<ExcitationSegment> out;
  Pressures now{};
  std::string part = "rest";
  // Moves to `p` (an edge as steep as allowed when it is a change) and holds it for `s` seconds.
  const auto hold = [&](const Pressures& p, double s) {
    double change = 0.0;
    for (std::size_t m = 0; m < p.size(); ++m) change = std::max(change, std::abs(p[m] - now[m]));
    if (change > 0.0) out.push_back({change / q.edge_rate_kpa_s, now, p, part});
    out.push_back({s, p, p, part});
    now = p;
  };
  const auto ramp = [&](const Pressures& p, double s) {
    out.push_back({s, now, p, part});
    now = p;
  };
  if (q.start_rest_s > 0.0) hold({}, q.start_rest_s);
  for (int m = 0; m < 4; ++m) {
    part = fmt::format("{} steps", kMuscleNames[static_cast<std::size_t>(m)]);
    for (double level : q.step_levels_kpa) hold(only(m, level), q.hold_s);
    hold({}, q.hold_s);
    part = fmt::format("{} ramp", kMuscleNames[static_cast<std::size_t>(m)]);
    ramp(only(m, top), q.ramp_s);
    ramp({}, q.ramp_s);
    hold({}, q.hold_s);
  }
  for (int pair = 0; pair < 2; ++pair) {
    Pressures both{};
    part = pair == 0 ? "flexor/extensor co-contraction" : "ulnar/radial co-contraction";
    for (double level : {q.co_contraction_kpa, top}) {
      both[static_cast<std::size_t>(2 * pair)] = both[static_cast<std::size_t>(2 * pair + 1)] = level;
      hold(both, q.hold_s);
    }
    hold({}, q.hold_s);
  }
  check_segments(out, max_kpa);
  return out;
}

double routine_duration_s(const std::vector<ExcitationSegment>& segments) {
  double total = 0.0;
  for (const auto& s : segments) total += s.duration_s;
  return total;
}

double routine_max_ramp_kpa_s(const std::vector<ExcitationSegment>& segments) {
  double steepest = 0.0;
  for (const auto& s : segments) {
    for (std::size_t m = 0; m < s.from_kpa.size(); ++m) {
      steepest = std::max(steepest, std::abs(s.to_kpa[m] - s.from_kpa[m]) / s.duration_s);
    }
  }
  return steepest;
}

ExcitationController::ExcitationController(std::vector<ExcitationSegment> segments, double max_kpa, double period_s)
    : segments_(std::move(segments)), period_s_(period_s), duration_s_(routine_duration_s(segments_)) {
  check_segments(segments_, max_kpa);
  if (!(period_s > 0.0)) throw std::invalid_argument("the excitation's period must be > 0 s");
}

Pressures ExcitationController::command(double t_s, const Reference&, const ImuReading&) {
  double start = 0.0;
  for (const ExcitationSegment& s : segments_) {
    if (t_s < start + s.duration_s) {
      const double f = std::clamp((t_s - start) / s.duration_s, 0.0, 1.0);
      Pressures p{};
      for (std::size_t m = 0; m < p.size(); ++m) p[m] = s.from_kpa[m] + f * (s.to_kpa[m] - s.from_kpa[m]);
      return p;
    }
    start += s.duration_s;
  }
  return {};
}

}  // namespace softwrist::control
