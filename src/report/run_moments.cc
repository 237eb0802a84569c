#include "report/run_moments.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "experiments/trial_log.h"
#include "physics/units.h"
#include "sim/wrist_sim.h"

namespace softwrist::report {
namespace {

namespace fs = std::filesystem;
using units::deg_to_rad;
using units::rad_to_deg;

constexpr std::array<const char*, 4> kPressureColumns = {"cmd_flexor_kpa", "cmd_extensor_kpa", "cmd_ulnar_kpa",
                                                         "cmd_radial_kpa"};

sim::DeviceDescription device_of(const experiments::LogHeader& header) {
  if (!header.config.is_object() || !header.config.contains("model")) return sim::paper_device();
  const auto& model = header.config["model"];
  if (!model.is_string()) throw std::runtime_error("trials.json: config.model: must be a path");
  fs::path path = model.get<std::string>();
  if (path.is_relative()) path = fs::path(header.config_dir) / path;
  return sim::load_device(path);
}

std::string describe(const WristPose& pose) {
  return fmt::format(
      "flexion {:.1f}°, ulnar deviation {:.1f}°; pressures {:.0f}/{:.0f}/{:.0f}/{:.0f} kPa "
      "(flexor/extensor/ulnar/radial)",
      rad_to_deg(pose.fe), rad_to_deg(pose.ur), pose.pressures_kpa[0], pose.pressures_kpa[1], pose.pressures_kpa[2],
      pose.pressures_kpa[3]);
}

View view_of(sim::MuscleIndex muscle) {
  return physics::axis_of(muscle) == physics::WristAxis::kFlexionExtension ? View::kRadial : View::kPalmar;
}

sim::MuscleIndex muscle_named(const io::CsvTable& table, std::size_t row, int column) {
  const auto muscle = sim::muscle_from_name(table.cell(row, column));
  if (!muscle) {
    throw std::runtime_error(
        fmt::format("{}:{}: muscle: unknown muscle '{}'", table.source(), table.line_of(row), table.cell(row, column)));
  }
  return *muscle;
}

// A muscle alone at its pressure, the wrist at `joint_angle` on that muscle's joint and `other_angle` on the other.
WristPose single_muscle_pose(sim::MuscleIndex muscle, double joint_angle, double other_angle, double pressure_kpa) {
  WristPose pose;
  const bool fe = physics::axis_of(muscle) == physics::WristAxis::kFlexionExtension;
  pose.fe = fe ? joint_angle : other_angle;
  pose.ur = fe ? other_angle : joint_angle;
  pose.pressures_kpa[muscle] = pressure_kpa;
  return pose;
}

std::vector<Moment> range_of_motion_moments(const io::CsvTable& t) {
  const int c_muscle = t.column("muscle"), c_rep = t.column("repetition"), c_pressure = t.column("pressure_kpa"),
            c_limit = t.column("limit_deg"), c_other = t.column("other_angle_deg");
  std::vector<Moment> moments;
  for (std::size_t row = 0; row < t.row_count(); ++row) {
    if (t.number(row, c_rep) != 0.0) continue;
    const sim::MuscleIndex muscle = muscle_named(t, row, c_muscle);
    const double limit = deg_to_rad(t.number(row, c_limit));  // in the muscle's own direction
    const WristPose pose = single_muscle_pose(muscle, physics::direction_of(muscle) * limit,
                                              deg_to_rad(t.number(row, c_other)), t.number(row, c_pressure));
    moments.push_back({fmt::format("rom_{}", sim::kMuscleNames[muscle]),
                       fmt::format("The {} alone at {:.0f} kPa, settled (first repetition): {}",
                                   sim::kMuscleNames[muscle], t.number(row, c_pressure), describe(pose)),
                       pose, view_of(muscle)});
  }
  return moments;
}

std::vector<Moment> torque_validation_moments(const experiments::LogHeader& header, const io::CsvTable& t) {
  const auto& name = header.config.value("muscle", std::string("flexor"));
  const auto muscle = sim::muscle_from_name(name);
  if (!muscle) throw std::runtime_error(fmt::format("trials.json: config.muscle: unknown muscle '{}'", name));
  const int c_angle = t.column("angle_deg"), c_pressure = t.column("pressure_kpa"), c_torque = t.column("torque_nm");
  if (t.row_count() == 0) return {};
  std::size_t best = 0;
  for (std::size_t row = 1; row < t.row_count(); ++row) {
    if (t.number(row, c_torque) > t.number(best, c_torque)) best = row;
  }
  const WristPose pose =
      single_muscle_pose(*muscle, deg_to_rad(t.number(best, c_angle)), 0.0, t.number(best, c_pressure));
  return {{"torque_peak",
           fmt::format("The {} on the torque rig at its largest measured torque, {:.2f} N m: {}", name,
                       t.number(best, c_torque), describe(pose)),
           pose, view_of(*muscle)}};
}

struct TrackingCase {
  int index = 0;  // the case's number in the log
  std::string controller;
  int repetition = 0;
  std::vector<TimedPose> poses;
  bool moves_fe = false, moves_ur = false;
};

TrackingCase tracking_case(const io::CsvTable& t, int case_index) {
  const int c_case = t.column("case"), c_controller = t.column("controller"), c_rep = t.column("repetition"),
            c_t = t.column("t_s");
  // The joint angles where the log has them (simulation), else what the IMUs measured (hardware).
  const auto angle_column = [&](const char* axis) {
    const int joint = t.find_column(fmt::format("true_{}_deg", axis));
    return joint >= 0 ? joint : t.column(fmt::format("measured_{}_deg", axis));
  };
  const int c_fe = angle_column("fe"), c_ur = angle_column("ur");
  // By default the log's first case: a trial of some of a config's controllers holds only their cases.
  if (case_index < 0 && t.row_count() > 0) case_index = t.integer(0, c_case);
  std::array<int, 4> c_pressure{};
  for (std::size_t i = 0; i < 4; ++i) c_pressure[i] = t.column(kPressureColumns[i]);

  TrackingCase result{.index = case_index};
  for (std::size_t row = 0; row < t.row_count(); ++row) {
    if (t.number(row, c_case) != case_index) continue;
    if (result.poses.empty()) {
      result.controller = t.cell(row, c_controller);
      result.repetition = t.integer(row, c_rep);
    }
    TimedPose p{t.number(row, c_t), {deg_to_rad(t.number(row, c_fe)), deg_to_rad(t.number(row, c_ur)), {}}};
    for (std::size_t i = 0; i < 4; ++i) p.pose.pressures_kpa[i] = t.number(row, c_pressure[i]);
    result.moves_fe = result.moves_fe || p.pose.pressures_kpa[0] > 0.0 || p.pose.pressures_kpa[1] > 0.0;
    result.moves_ur = result.moves_ur || p.pose.pressures_kpa[2] > 0.0 || p.pose.pressures_kpa[3] > 0.0;
    result.poses.push_back(p);
  }
  if (result.poses.empty()) {
    throw std::runtime_error(fmt::format("{}: no rows of case {}", t.source(), case_index));
  }
  return result;
}

std::vector<Moment> tracking_moments(const io::CsvTable& t, const MomentQuery& query) {
  const TrackingCase c = tracking_case(t, query.case_index);
  const std::string who = fmt::format("{} controller, repetition {}", c.controller, c.repetition);
  const auto moment = [&](const TimedPose& p, const std::string& what, const std::string& name, View view) {
    return Moment{fmt::format("case{}_{}", c.index, name),
                  fmt::format("{}, {} at t = {:.2f} s: {} (commanded)", who, what, p.t, describe(p.pose)), p.pose,
                  view};
  };
  std::vector<Moment> moments;
  if (query.at_s) {
    const double at = *query.at_s;
    if (!std::isfinite(at) || at < c.poses.front().t || at > c.poses.back().t) {
      throw std::runtime_error(fmt::format("--at {} s is outside case {} ({:.2f} to {:.2f} s)", at, c.index,
                                           c.poses.front().t, c.poses.back().t));
    }
    const auto nearest = std::min_element(c.poses.begin(), c.poses.end(), [at](const TimedPose& a, const TimedPose& b) {
      return std::abs(a.t - at) < std::abs(b.t - at);
    });
    const std::string stem = fmt::format("t{:.2f}", nearest->t);
    if (c.moves_fe || !c.moves_ur) moments.push_back(moment(*nearest, "the wrist", stem + "_radial", View::kRadial));
    if (c.moves_ur) moments.push_back(moment(*nearest, "the wrist", stem + "_palmar", View::kPalmar));
    return moments;
  }
  const auto extreme = [&](auto angle, bool largest) {
    return *std::max_element(c.poses.begin(), c.poses.end(), [&](const TimedPose& a, const TimedPose& b) {
      return largest ? angle(a) < angle(b) : angle(a) > angle(b);
    });
  };
  const auto fe = [](const TimedPose& p) { return p.pose.fe; };
  const auto ur = [](const TimedPose& p) { return p.pose.ur; };
  if (c.moves_fe) {
    moments.push_back(moment(extreme(fe, true), "most flexed", "most_flexed", View::kRadial));
    moments.push_back(moment(extreme(fe, false), "most extended", "most_extended", View::kRadial));
  }
  if (c.moves_ur) {
    moments.push_back(moment(extreme(ur, true), "most ulnar", "most_ulnar", View::kPalmar));
    moments.push_back(moment(extreme(ur, false), "most radial", "most_radial", View::kPalmar));
  }
  return moments;
}

}  // namespace

sim::DeviceDescription run_device(const fs::path& run_dir) {
  return device_of(experiments::read_log(run_dir, "trials").header);
}

RunMoments run_moments(const fs::path& run_dir, const MomentQuery& query) {
  const experiments::TrialLog log = experiments::read_log(run_dir, "trials");
  const std::string& kind = log.header.kind;
  if (query.at_s && kind != "tracking") {
    throw std::runtime_error(fmt::format("--at needs a tracking run; {} is a {} run", run_dir.string(), kind));
  }
  RunMoments result{device_of(log.header), {}};
  if (kind == "range_of_motion") result.moments = range_of_motion_moments(log.table);
  if (kind == "torque_validation") result.moments = torque_validation_moments(log.header, log.table);
  if (kind == "tracking") result.moments = tracking_moments(log.table, query);
  return result;
}

std::vector<TimedPose> tracking_timeline(const fs::path& run_dir, int case_index) {
  const experiments::TrialLog log = experiments::read_log(run_dir, "trials");
  if (log.header.kind != "tracking") {
    throw std::runtime_error(
        fmt::format("{} is a {} run; a video needs a tracking run", run_dir.string(), log.header.kind));
  }
  return tracking_case(log.table, case_index).poses;
}

}  // namespace softwrist::report
