#include "diagnosis/synthetic_device.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <utility>

#include "experiments/trial_log.h"
#include "io/csv.h"
#include "physics/fpam_force.h"
#include "physics/paper_parameters.h"
#include "physics/units.h"
#include "sim/model.h"
#include "sim/model_builder.h"
#include "sim/plugins.h"
#include "sim/wrist_sim.h"
#include "sim/wrist_statics.h"

namespace softwrist::diagnosis {
namespace {

namespace fs = std::filesystem;
using io::format_number;
using units::deg_to_rad;
using units::rad_to_deg;

experiments::LogWriter open_log(const fs::path& dir, const std::string& kind, std::vector<experiments::Column> columns,
                                nlohmann::json config) {
  fs::create_directories(dir);
  experiments::LogHeader header{
      .kind = kind, .source = "synthetic", .config = std::move(config), .columns = std::move(columns), .case_count = 1};
  return experiments::LogWriter(dir, "trials", header);
}

sim::Model load(const SyntheticDevice& real, const sim::PluginSet& plugins, double gravity) {
  sim::ModelOptions options;
  options.gravity = gravity;
  // The fabric's hysteresis as a state of the muscles' force in MuJoCo (physics/fpam_hysteresis.h): the range of
  // motion and the trajectories show it, as a real fabric muscle's would; the tensile rig keeps its own form below.
  sim::DeviceDescription device = real.device;
  device.hysteresis.fraction = real.hysteresis;
  std::string xml = sim::build_model_xml(device, options);
  if (real.wrap_friction_n > 0.0) xml = sim::with_tendon_friction(std::move(xml), real.wrap_friction_n);
  return sim::Model::FromXml(xml, plugins, "synthetic device");
}

void write_sweep(const SyntheticDevice& real, const SyntheticPlan& plan, const sim::PluginSet& plugins,
                 std::mt19937_64& rng, const fs::path& out) {
  std::normal_distribution<double> normal;
  auto log = open_log(out / "torque_sweep", "torque_sweep",
                      {{"repetition", "", ""},
                       {"muscle", "", ""},
                       {"angle_deg", "deg", ""},
                       {"pressure_kpa", "kPa", ""},
                       {"torque_nm", "N m", ""}},
                      {{"muscle", "flexor"}});
  const sim::Model model = load(real, plugins, sim::kStandardGravity);
  sim::WristSim wrist(model);
  // The rig reads the torque once the regulator has settled (within 0.03 % after 8 time constants), at least 1 s.
  const double hold_s = std::max(1.0, 8.0 * real.device.regulator.time_constant);
  for (double angle_deg : {-67.5, -45.0, -22.5, 0.0, 22.5, 45.0, 67.5, 90.0}) {
    for (double kpa : {0.0, 34.0, 68.0, 103.0, 137.0}) {
      for (int rep = 0; rep < plan.repetitions; ++rep) {
        const double actual = angle_deg + plan.noise.angle_jitter_deg * normal(rng);
        wrist.reset();
        wrist.command_pressures_kpa({kpa, 0.0, 0.0, 0.0});
        wrist.run_held(hold_s, deg_to_rad(actual), 0.0);
        const double torque = wrist.muscle_torque(sim::kFlexor) + plan.noise.torque_nm * normal(rng);
        log.write_row(
            {std::to_string(rep), "flexor", format_number(actual), format_number(kpa), format_number(torque)});
      }
    }
  }
}

void write_rom(const SyntheticDevice& real, const SyntheticPlan& plan, const sim::PluginSet& plugins,
               std::mt19937_64& rng, const fs::path& out) {
  std::normal_distribution<double> normal;
  auto log =
      open_log(out / "range_of_motion", "range_of_motion",
               {{"repetition", "", ""}, {"muscle", "", ""}, {"pressure_kpa", "kPa", ""}, {"limit_deg", "deg", ""}},
               {{"hand_supported", false}});
  const sim::Model model = load(real, plugins, sim::kStandardGravity);
  sim::WristSim wrist(model);
  for (int m = 0; m < 4; ++m) {
    const auto muscle = static_cast<sim::MuscleIndex>(m);
    wrist.reset();
    std::array<double, 4> command{};
    command[static_cast<std::size_t>(m)] = 137.0;
    wrist.command_pressures_kpa(command);
    wrist.run(6.0);  // settled: the same wrist settles the same way every repetition; only the measurement differs
    const double limit = rad_to_deg(physics::direction_of(muscle) * wrist.angle(physics::axis_of(muscle)));
    for (int rep = 0; rep < plan.repetitions; ++rep) {
      log.write_row({std::to_string(rep), sim::kMuscleNames[static_cast<std::size_t>(m)], "137",
                     format_number(limit + plan.noise.rom_deg * normal(rng))});
    }
  }
}

void write_tensile(const SyntheticDevice& real, const SyntheticPlan& plan, std::mt19937_64& rng, const fs::path& out) {
  std::normal_distribution<double> normal;
  auto log = open_log(out / "tensile", "tensile",
                      {{"cycle", "", ""},
                       {"direction", "", ""},
                       {"pressure_kpa", "kPa", ""},
                       {"contraction", "", ""},
                       {"force_n", "N", ""}},
                      nlohmann::json::object());
  for (int cycle = 0; cycle < plan.repetitions; ++cycle) {
    for (double kpa : {0.0, 34.0, 68.0, 103.0, 137.0}) {
      const double eps_max = real.device.fpam.at_pressure(units::kpa_to_pa(kpa)).max_contraction;
      for (const bool loading : {true, false}) {
        for (int k = 0; k <= 12; ++k) {
          const double eps = eps_max * (loading ? 12 - k : k) / 12.0;  // loading stretches: contraction falls
          const double sign = loading ? 1.0 : -1.0;
          const double pressure = units::kpa_to_pa(kpa);
          const double force = physics::fpam_force(real.device.fpam, pressure, eps) * (1.0 + sign * real.hysteresis) +
                               sign * real.hysteresis_friction * physics::fpam_force(real.device.fpam, pressure, 0.0) +
                               plan.noise.force_n * normal(rng);
          log.write_row({std::to_string(cycle), loading ? "loading" : "unloading", format_number(kpa),
                         format_number(eps), format_number(force)});
        }
      }
    }
  }
}

// Antagonistic pressure sinusoids on both axes (90 degrees apart, period 12 s), or steps (plan.trajectory_steps), rows
// every 14 ms as the control loop logs them, the IMUs sampled every 10 ms.
void write_trajectory(const SyntheticDevice& real, const SyntheticPlan& plan, const sim::PluginSet& plugins,
                      std::mt19937_64& rng, const fs::path& out) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> jitter(-real.imu_latency_jitter, real.imu_latency_jitter);
  std::vector<experiments::Column> columns = {{"case", "", ""}, {"t_s", "s", ""}};
  for (const char* m : sim::kMuscleNames) columns.push_back({std::string("cmd_") + m + "_kpa", "kPa", ""});
  columns.push_back({"measured_fe_deg", "deg", ""});
  columns.push_back({"measured_ur_deg", "deg", ""});
  if (plan.measured_pressures) {
    for (const char* m : sim::kMuscleNames) columns.push_back({std::string("p_") + m + "_kpa", "kPa", ""});
  }
  auto log = open_log(out / "trajectory", "trajectory", columns, {{"hand_supported", true}});
  const sim::Model model = load(real, plugins, 0.0);
  sim::WristSim wrist(model);
  wrist.reset();
  const double dt = model->opt.timestep, period = 12.0, loop = 0.014, imu_period = 0.01;
  const auto command_at = [&](double t) -> std::array<double, 4> {
    if (t < 0.0) return {};
    // Steps: each axis's level from a fixed sequence that fills and vents by large and small amounts.
    static constexpr std::array<double, 7> kLevels = {1.0, -0.5, 0.8, -1.0, 0.3, -0.8, 0.0};
    const auto step = static_cast<std::size_t>(t / 1.5);
    const double a =
        plan.trajectory_steps ? kLevels[step % kLevels.size()] : std::sin(2.0 * std::numbers::pi * t / period);
    const double b =
        plan.trajectory_steps ? kLevels[(step + 3) % kLevels.size()] : std::cos(2.0 * std::numbers::pi * t / period);
    return {45.0 + 40.0 * a, 45.0 - 40.0 * a, 45.0 + 40.0 * b, 45.0 - 40.0 * b};
  };
  // The true angles every step, kept for the IMU's late samples.
  std::vector<std::array<double, 2>> history;
  double next_row = 0.0;
  const auto steps = static_cast<std::size_t>(plan.trajectory_s / dt);
  std::array<double, 4> prefiltered{};  // the second regulator stage's output
  for (std::size_t k = 0; k <= steps; ++k) {
    const double t = static_cast<double>(k) * dt;
    // Commands are logged on the loop's ticks and reach the regulators dead_time later.
    const double commanded = std::floor((t - real.regulator_dead_time) / loop + 1e-9) * loop;
    std::array<double, 4> command = command_at(commanded);
    if (real.regulator_prefilter_time_constant > 0.0) {
      const double a = 1.0 - std::exp(-dt / real.regulator_prefilter_time_constant);  // exact first-order step
      for (std::size_t m = 0; m < 4; ++m) command[m] = prefiltered[m] += a * (command[m] - prefiltered[m]);
    }
    wrist.command_pressures_kpa(command);
    history.push_back(
        {wrist.angle(physics::WristAxis::kFlexionExtension), wrist.angle(physics::WristAxis::kUlnarRadial)});
    if (t + 1e-9 >= next_row) {
      const double late = real.imu_latency + (real.imu_latency_jitter > 0.0 ? jitter(rng) : 0.0);
      const double sampled = std::max(0.0, std::floor((t - late) / imu_period + 1e-9) * imu_period);
      const auto& angles = history[std::min(history.size() - 1, static_cast<std::size_t>(std::lround(sampled / dt)))];
      const auto cmd = command_at(std::floor(t / loop + 1e-9) * loop);
      std::vector<std::string> row = {"0", format_number(t)};
      for (double p : cmd) row.push_back(format_number(p));
      const double c = std::cos(deg_to_rad(real.imu_axis_roll_deg)), s = std::sin(deg_to_rad(real.imu_axis_roll_deg));
      const double fe = c * angles[0] - s * angles[1], ur = s * angles[0] + c * angles[1];
      row.push_back(format_number(rad_to_deg(fe) + real.imu_offset_fe_deg + plan.noise.imu_deg * normal(rng)));
      row.push_back(format_number(rad_to_deg(ur) + real.imu_offset_ur_deg + plan.noise.imu_deg * normal(rng)));
      if (plan.measured_pressures) {
        for (std::size_t m = 0; m < 4; ++m) {
          const double p = wrist.regulated_pressure_kpa(static_cast<sim::MuscleIndex>(m));
          row.push_back(format_number(p + plan.noise.pressure_kpa * normal(rng)));
        }
      }
      log.write_row(row);
      next_row += loop;
    }
    wrist.run(dt);
  }
}

}  // namespace

void write_synthetic_data(const SyntheticDevice& real, const SyntheticPlan& plan, const fs::path& out) {
  const sim::PluginSet plugins = sim::PluginSet::Default();
  std::mt19937_64 rng(plan.seed);
  if (plan.torque_sweep) write_sweep(real, plan, plugins, rng, out);
  if (plan.range_of_motion) write_rom(real, plan, plugins, rng, out);
  if (plan.tensile) write_tensile(real, plan, rng, out);
  if (plan.trajectory) write_trajectory(real, plan, plugins, rng, out);
}

}  // namespace softwrist::diagnosis
