#include "experiments/range_of_motion.h"

#include <cmath>
#include <map>

#include <fmt/format.h>

#include "io/csv.h"
#include "physics/paper_parameters.h"
#include "physics/range_of_motion.h"
#include "physics/units.h"
#include "sim/wrist_sim.h"
#include "sim/wrist_statics.h"

namespace softwrist::experiments {
namespace {

using io::format_number;
using units::deg_to_rad;
using units::rad_to_deg;

}  // namespace

std::unique_ptr<RangeOfMotion> RangeOfMotion::Create(const ExperimentConfig& config, io::JsonReader& reader) {
  auto e = std::unique_ptr<RangeOfMotion>(new RangeOfMotion());
  e->device_ = std::make_unique<SimulatedDevice>(config_path(reader, "model", config));
  if (reader.has("muscles")) {
    const nlohmann::json& list = reader.raw("muscles");
    if (!list.is_array() || list.empty()) reader.fail("muscles", "must be a non-empty list of muscle names");
    for (const auto& item : list) {
      const auto muscle = item.is_string() ? sim::muscle_from_name(item.get<std::string>()) : std::nullopt;
      if (!muscle) reader.fail("muscles", fmt::format("{} is not flexor, extensor, ulnar or radial", item.dump()));
      e->muscles_.push_back(*muscle);
    }
  } else {
    e->muscles_ = {sim::kFlexor, sim::kExtensor, sim::kUlnar, sim::kRadial};
  }
  e->pressure_ = e->device_->regulator_pressure(reader, "pressure_kpa",
                                                reader.number("pressure_kpa", physics::kRegulatorMaxPressureKpa));
  const Repetitions repetitions = read_repetitions(reader);
  e->repetitions_ = repetitions.count;
  e->seed_ = repetitions.seed;
  e->settle_time_ = reader.positive("settle_time_s", 6.0);
  if (reader.has("sensor_noise")) {
    io::JsonReader noise = reader.child("sensor_noise");
    e->angle_std_ = deg_to_rad(noise.non_negative("angle_std_deg", 0.5));
    noise.finish();
  }
  return e;
}

std::vector<Column> RangeOfMotion::columns() const {
  return {{"repetition", "", "repetition, from 0"},
          {"muscle", "", "the pressurised muscle"},
          {"pressure_kpa", "kPa", "its commanded pressure (the others at 0)"},
          {"limit_deg", "deg", "measured settled wrist angle in the muscle's own direction"},
          {"other_angle_deg", "deg", "the other wrist angle at the same time (flexion, ulnar positive)"},
          {"residual_velocity_deg_s", "deg/s", "joint speed at the end of the settling time"}};
}

std::vector<Row> RangeOfMotion::run_case(int index) const {
  const int repetition = index % repetitions_;
  const sim::MuscleIndex muscle = muscles_[static_cast<std::size_t>(index / repetitions_)];
  std::mt19937_64 rng = case_rng(seed_, index);
  std::normal_distribution<double> normal(0.0, 1.0);
  sim::WristSim wrist(device_->model);
  std::array<double, 4> command{};
  command[muscle] = units::pa_to_kpa(pressure_);
  wrist.command_pressures_kpa(command);
  wrist.run(settle_time_);
  const physics::WristAxis joint = physics::axis_of(muscle);
  const physics::WristAxis other = joint == physics::WristAxis::kFlexionExtension
                                       ? physics::WristAxis::kUlnarRadial
                                       : physics::WristAxis::kFlexionExtension;
  const double limit = physics::direction_of(muscle) * wrist.angle(joint) + angle_std_ * normal(rng);
  const double other_angle = wrist.angle(other) + angle_std_ * normal(rng);
  return {{std::to_string(repetition), sim::kMuscleNames[muscle], format_number(units::pa_to_kpa(pressure_)),
           format_number(rad_to_deg(limit)), format_number(rad_to_deg(other_angle)),
           format_number(rad_to_deg(std::abs(wrist.velocity(joint))))}};
}

nlohmann::json RangeOfMotion::summarize(const io::CsvTable& log, const std::filesystem::path&) const {
  const int c_muscle = log.column("muscle"), c_limit = log.column("limit_deg"), c_pressure = log.column("pressure_kpa");
  struct Stats {
    int n = 0;
    double sum = 0.0, sum_sq = 0.0, pressure_kpa = 0.0;
  };
  std::map<std::string, Stats> by_muscle;
  for (std::size_t row = 0; row < log.row_count(); ++row) {
    Stats& s = by_muscle[log.cell(row, c_muscle)];
    const double v = log.number(row, c_limit);
    s.n += 1;
    s.sum += v;
    s.sum_sq += v * v;
    s.pressure_kpa = log.number(row, c_pressure);
  }
  const sim::DeviceDescription& device = device_->description;
  const auto direction_name = [](sim::MuscleIndex m) {
    constexpr std::array<const char*, 4> names = {"flexion", "extension", "ulnar", "radial"};
    return names[m];
  };
  const std::array<double, 4> biological = {device.wrist.flexion_limit, device.wrist.extension_limit,
                                            device.wrist.ulnar_limit, device.wrist.radial_limit};
  nlohmann::json muscles = nlohmann::json::array();
  for (const auto& [name, s] : by_muscle) {
    const auto muscle = sim::muscle_from_name(name);
    if (!muscle) throw std::runtime_error(log.source() + ": muscle '" + name + "' is not one of the four");
    const double pressure = units::kpa_to_pa(s.pressure_kpa);
    const double mean = s.sum / s.n;
    const double std = s.n > 1 ? std::sqrt(std::max(0.0, (s.sum_sq - s.n * mean * mean) / (s.n - 1))) : 0.0;
    physics::Muscle fixed = device.muscle(*muscle);
    fixed.stretch_mode = physics::StretchMode::kNone;
    const auto limit = physics::joint_limit(fixed, pressure, deg_to_rad(90.0));
    const double statics = sim::settled_angle(device, *muscle, pressure);
    const auto torques = sim::static_torques(device, *muscle, pressure, statics);
    const auto& paper = physics::paper::rom_table()[*muscle];
    muscles.push_back({{"muscle", name},
                       {"direction", direction_name(*muscle)},
                       {"pressure_kpa", s.pressure_kpa},
                       {"settled_deg", mean},
                       {"settled_std_deg", std},
                       {"repetitions", s.n},
                       {"analytic_limit_deg", limit ? nlohmann::json(rad_to_deg(*limit)) : nlohmann::json(nullptr)},
                       {"analytic_settled_deg", rad_to_deg(statics)},
                       {"at_analytic_settled_nm",
                        {{"muscle", torques.muscle},
                         {"antagonist", torques.antagonist},
                         {"passive_wrist", torques.passive},
                         {"gravity", torques.gravity}}},
                       {"model_biological_limit_deg", rad_to_deg(biological[*muscle])},
                       {"paper_exosuit_deg", paper.exosuit_deg},
                       {"paper_exosuit_std_deg", paper.exosuit_std_deg},
                       {"paper_biological_deg", paper.biological_deg},
                       {"paper_modeled_limit_deg", paper.paper_modeled_limit_deg()}});
  }
  return {{"muscles", muscles},
          {"explanation",
           "analytic_limit_deg is the paper's modeled limit: where the muscle's own torque reaches zero, with the "
           "fixed placement and no stretching. The wrist settles short of it because other torques act before that "
           "point: the mounts stretch (the muscle is shorter, so its torque reaches zero earlier), the relaxed "
           "wrist's stiffness pulls back, the deflated antagonist's fabric pulls back once stretched, the hand's "
           "weight acts on ulnar/radial deviation, and the joint stops at the biological limit. "
           "analytic_settled_deg solves the analytic statics with all of these (at_analytic_settled_nm lists them); "
           "the simulated settled angle agrees with it up to the 3D tendon geometry and the noise."}};
}

}  // namespace softwrist::experiments
