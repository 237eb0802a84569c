#include "independent_device/rigs.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "independent_device/controller.h"
#include "independent_device/units.h"

namespace softwrist::independent {
namespace {

constexpr double kDynamicsDt = 1e-3;  // wrist dynamics step [s]
constexpr int kImuPeriodMs = 10;      // BNO055 fusion output at 100 Hz
constexpr int kControlPeriodMs = 14;  // the paper's loop time

// The prototype on the arm: four channels, four muscles, the wrist.
struct PrototypeSim {
  Session& s;
  Posture posture;
  bool ur_locked;
  WristCondition condition;
  WristState wrist;
  std::array<double, 4> last_force_n{-1.0, -1.0, -1.0, -1.0};

  void step(const std::array<double, 4>& command_kpa) {
    std::array<double, 4> pressure{};
    for (std::size_t i = 0; i < 4; ++i) {
      s.regulators[i].step(command_kpa[i], kDynamicsDt);
      pressure[i] = s.regulators[i].muscle_kpa(s.clock_s);
    }
    const std::array<double, 4> own{wrist.fe, -wrist.fe, wrist.ur, -wrist.ur};
    std::array<MuscleForce, 4> out;
    for (std::size_t i = 0; i < 4; ++i) {
      out[i] = solve_muscle(s.device.prototype[i], s.prototype[i], own[i], pressure[i], last_force_n[i]);
      last_force_n[i] = out[i].force_n;
    }
    const auto passive = passive_torque_nm(s.device.passive, condition, wrist);
    const auto gravity = gravity_torque_nm(s.device.hand, posture, wrist.fe, wrist.ur);
    const std::array<double, 2> torque{out[kFlexor].torque_nm - out[kExtensor].torque_nm + passive[0] + gravity[0],
                                       out[kUlnar].torque_nm - out[kRadial].torque_nm + passive[1] + gravity[1]};
    step_wrist(wrist, s.device.hand, torque, kDynamicsDt, ur_locked);
    for (std::size_t i = 0; i < 4; ++i)
      advance_muscle(s.device.prototype[i], s.prototype[i], out[i], pressure[i], kDynamicsDt);
    s.clock_s += kDynamicsDt;
  }
};

// The subject's state for one trial: where the relaxed wrist rests, how toned it is (scatter between trials).
WristCondition draw_condition(Rng& rng, bool noisy) {
  const double rest_fe = rng.normal(0.0, 1.5), rest_ur = rng.normal(0.0, 1.5), tone = rng.normal(1.0, 0.08);
  WristCondition c;
  if (noisy) {
    c.rest_fe_rad = to_rad(rest_fe);
    c.rest_ur_rad = to_rad(rest_ur);
    c.stiffness_scale = tone;
  }
  return c;
}

// Runs the prototype `ms` milliseconds under `command` with the IMU pair observing every step and sampling every
// kImuPeriodMs from `phase`; `n` counts the steps since the trial began.
void run_sampled(PrototypeSim& sim, ImuPair& imu, const std::array<double, 4>& command, int phase, int& n, int ms) {
  for (int k = 0; k < ms; ++k, ++n) {
    sim.step(command);
    const double time = n * kDynamicsDt;
    imu.observe(time, sim.wrist.fe, sim.wrist.ur);
    if ((n + phase) % kImuPeriodMs == 0) imu.sample(time);
  }
}

}  // namespace

Session::Session(const DeviceSpec& spec, std::uint64_t session_seed, bool with_noise)
    : device(spec), seed(session_seed), noisy(with_noise) {
  for (const auto& r : device.regulators) regulators.emplace_back(r);
}

MuscleForce torque_rig_flexor(const DeviceSpec& device, const MuscleState& state, double angle_rad,
                              double pressure_kpa) {
  return solve_muscle(device.rig_flexor, state, angle_rad, pressure_kpa);
}

// --- tensile test --------------------------------------------------------------------------------------------
Table run_tensile(Session& s) {
  Table t{{"pressure_kpa", "contraction", "force_n", "direction", "cycle"}, {}};
  Rng sensor(s.seed, "tensile-load-cell");
  const MuscleSpec& spec = s.device.tensile_specimen;
  Regulator& reg = s.regulators[kFlexor];
  const double tester_l0 = 0.34;           // the length the tester's contraction refers to (measured L0, Table tensile)
  const FpamLaw table_law;                 // the operator starts each test at the contraction the paper's table shows
  constexpr double kStepsPerUnit = 200.0;  // contraction grid 0.005
  constexpr double kPointS = 1.0;          // crosshead ~100 mm/min: 1.7 mm per grid step
  auto at = [&](int index, double command_kpa, double dt) {
    reg.step(command_kpa, dt);
    const double p = reg.muscle_kpa(s.clock_s);
    const MuscleForce f = solve_muscle_at_length(spec, s.flexor_fpam, tester_l0 * (1.0 - index / kStepsPerUnit), p);
    advance_muscle(spec, s.flexor_fpam, f, p, dt);
    s.clock_s += dt;
    return f;
  };
  for (const double pressure : kPaperPressuresKpa) {
    const int start = static_cast<int>(std::ceil((max_contraction(table_law, pressure) + 0.01) * kStepsPerUnit));
    for (int k = 0; k < 2000; ++k) at(start, pressure, 0.01);  // inflate at the contracted length; settle 20 s
    for (int cycle = 1; cycle <= 3; ++cycle) {
      for (int dir = 0; dir < 2; ++dir) {
        const bool loading = dir == 0;
        const int first = loading ? start : 1, last = loading ? 0 : start, step = loading ? -1 : 1;
        for (int i = first;; i += step) {
          const MuscleForce f = at(i, pressure, kPointS);
          t.rows.push_back({pressure, i / kStepsPerUnit,
                            read_tensile_load_cell_n(f.force_n, s.noisy ? &sensor : nullptr),
                            std::string(loading ? "loading" : "unloading"), static_cast<double>(cycle)});
          if (i == last) break;
        }
      }
    }
    for (int k = 0; k < 500; ++k) at(start, 0.0, 0.01);  // vent
  }
  return t;
}

// --- torque sweep ----------------------------------------------------------------------------------------------
Table run_torque_sweep(Session& s, const std::string& torque_includes, Posture posture, int repetitions) {
  Table t{{"angle_deg", "pressure_kpa", "torque_nm", "repetition", "muscle"}, {}};
  Rng human(s.seed, "sweep-human"), sensor(s.seed, "sweep-torque-sensor");
  Regulator& reg = s.regulators[kFlexor];
  constexpr double kDt = 0.01;
  const std::array<double, 8> angles{-67.5, -45.0, -22.5, 0.0, 22.5, 45.0, 67.5, 90.0};  // paper, 22.5 deg steps
  const bool passive = torque_includes != "muscle";
  const bool weight = torque_includes == "muscle+passive_wrist+hand_weight" || torque_includes == "baseline_subtracted";
  double plate = to_rad(angles.front());
  double offset_error = 0.0;  // the hand's angle error on the plate for the current setting
  auto hold = [&](double command_kpa, double seconds) {
    MuscleForce f;
    const int n = static_cast<int>(std::lround(seconds / kDt));
    for (int k = 0; k < n; ++k) {
      reg.step(command_kpa, kDt);
      const double p = reg.muscle_kpa(s.clock_s);
      f = torque_rig_flexor(s.device, s.flexor_fpam, plate + s.device.rig_angle_offset_rad + offset_error, p);
      advance_muscle(s.device.rig_flexor, s.flexor_fpam, f, p, kDt);
      s.clock_s += kDt;
    }
    return f;
  };
  for (int rep = 1; rep <= repetitions; ++rep) {
    const bool ascending = rep % 2 == 1;
    for (std::size_t a = 0; a < angles.size(); ++a) {
      const double angle_deg = ascending ? angles[a] : angles[angles.size() - 1 - a];
      hold(0.0, 2.0);  // vent, then screw the plate to the next angle (0.5 deg per 20 ms)
      const double target = to_rad(angle_deg);
      while (std::abs(plate - target) > 1e-12) {
        plate += std::clamp(target - plate, -to_rad(0.5), to_rad(0.5));
        hold(0.0, 0.02);
      }
      // Human scatter of this setting: the hand's seat on the plate, the relaxed wrist's tone.
      const double seat = human.normal(0.0, 0.3), tone_scale = human.normal(1.0, 0.08), tone = human.normal(0.0, 0.02);
      offset_error = s.noisy ? to_rad(seat) : 0.0;
      WristCondition condition;
      if (s.noisy) condition.stiffness_scale = tone_scale;
      const double wrist = plate + s.device.rig_angle_offset_rad + offset_error;
      const double passive_nm =
          passive_torque_nm(s.device.passive, condition, WristState{wrist, 0.0, 0.0, 0.0})[0] + (s.noisy ? tone : 0.0);
      const double weight_nm = gravity_torque_nm(s.device.hand, posture, wrist, 0.0)[0];
      std::array<double, 5> reading{};
      std::array<double, 5> pressure{};
      for (std::size_t k = 0; k < 5; ++k) {
        pressure[k] = ascending ? kPaperPressuresKpa[k] : kPaperPressuresKpa[4 - k];
        const MuscleForce f = hold(pressure[k], 4.0);
        const double load = f.torque_nm + (passive ? passive_nm : 0.0) + (weight ? weight_nm : 0.0);
        reading[k] = read_torque_sensor_nm(load, s.noisy ? &sensor : nullptr);
      }
      const double baseline = ascending ? reading.front() : reading.back();  // the 0 kPa reading at this angle
      for (std::size_t k = 0; k < 5; ++k) {
        double value = reading[k];
        if (torque_includes == "baseline_subtracted")
          value = s.noisy ? quantise(value - baseline, 1000.0) : value - baseline;
        t.rows.push_back({angle_deg, pressure[k], value, static_cast<double>(rep), std::string("flexor")});
      }
    }
  }
  hold(0.0, 2.0);
  return t;
}

// --- range of motion -------------------------------------------------------------------------------------------
Table run_rom(Session& s, Posture posture, int repetitions) {
  Table t{{"muscle", "pressure_kpa", "limit_deg", "repetition"}, {}};
  Rng human(s.seed, "rom-human");
  PrototypeSim sim{s, posture, false, {}, {}};
  const std::array<double, 4> off{};
  for (int k = 0; k < 3000; ++k) sim.step(off);  // donned and relaxed
  std::uint64_t trial = 0;
  for (int rep = 1; rep <= repetitions; ++rep) {
    for (std::size_t m = 0; m < 4; ++m) {
      for (std::size_t p = 1; p < kPaperPressuresKpa.size(); ++p) {  // 0 kPa has no limit to measure
        sim.condition = draw_condition(human, s.noisy);
        const int phase = static_cast<int>(human.uniform() * kImuPeriodMs);
        ImuPair imu(s.device.imu, s.seed, 1000 + trial++, s.noisy);
        std::array<double, 4> command{};
        int n = 0;
        auto run = [&](int ms) { run_sampled(sim, imu, command, phase, n, ms); };
        run(2500);  // relaxing from the previous trial
        imu.zero();
        command[m] = kPaperPressuresKpa[p];
        run(4000);
        const double reading = m < 2 ? imu.fe_deg() : imu.ur_deg();
        const double limit = (m % 2 == 0 ? 1.0 : -1.0) * reading + 0.0;
        t.rows.push_back({std::string(kMuscleNames[m]), kPaperPressuresKpa[p], limit, static_cast<double>(rep)});
      }
    }
  }
  for (int k = 0; k < 2000; ++k) sim.step(off);
  return t;
}

// --- closed-loop tracking --------------------------------------------------------------------------------------
Table run_tracking(Session& s, TrackingTask task, Posture posture, int trials, double length_s) {
  Table t{{"case", "t_s", "cmd_flexor_kpa", "cmd_extensor_kpa", "cmd_ulnar_kpa", "cmd_radial_kpa", "angle_fe_deg",
           "angle_ur_deg", "p_flexor_kpa", "p_extensor_kpa", "p_ulnar_kpa", "p_radial_kpa"},
          {}};
  const bool planar = task == TrackingTask::planar_steps;
  const std::string name = planar ? "steps" : "ellipse";
  Rng human(s.seed, "tracking-human-" + name);
  PrototypeSim sim{s, posture, planar, {}, {}};
  const int total_ms = static_cast<int>(std::lround(length_s * 1000.0));
  // Planar task (paper Sec. "Planar angle tracking"): 0 to 30 deg extension and on to 40 deg flexion in 10 deg
  // steps, each held for a 1/11 of the trial (10 s in the paper's 110 s trial).
  const std::array<double, 11> steps{0, -10, -20, -30, -20, -10, 0, 10, 20, 30, 40};
  auto desired = [&](double time) -> std::array<double, 2> {
    if (planar) {
      const auto i = std::min<std::size_t>(10, static_cast<std::size_t>(time / (length_s / 11.0)));
      return {steps[i], 0.0};
    }
    // Spatial task: FE in [-40, 30], UR in [-10, 30] deg, period 24 s, 90 deg apart (paper Sec. "Spatial ...").
    const double w = 2.0 * kPi / 24.0;
    return {-5.0 + 35.0 * std::sin(w * time), 10.0 - 20.0 * std::cos(w * time)};
  };
  for (int trial = 0; trial < trials; ++trial) {
    Rng monitor(s.seed, "tracking-monitor-" + name, static_cast<std::uint64_t>(trial));
    sim.condition = draw_condition(human, s.noisy);
    const double place_fe = human.normal(0.0, 2.0), place_ur = human.normal(0.0, 2.0);
    const int preroll_ms = 300 + static_cast<int>(human.uniform() * 700.0);
    const int phase = static_cast<int>(human.uniform() * kImuPeriodMs);
    // Vent after the previous trial, then the experimenter sets the hand near rest and the initial pressures fill.
    std::array<double, 4> command{};
    for (int k = 0; k < 2000; ++k) sim.step(command);
    sim.wrist = {sim.condition.rest_fe_rad + (s.noisy ? to_rad(place_fe) : 0.0),
                 planar ? 0.0 : sim.condition.rest_ur_rad + (s.noisy ? to_rad(place_ur) : 0.0), 0.0, 0.0};
    PaperController controller;
    controller.reset(true, !planar);
    command = controller.command_kpa;
    ImuPair imu(s.device.imu, s.seed, (planar ? 5000u : 6000u) + static_cast<std::uint64_t>(trial), s.noisy);
    int n = 0;
    auto run = [&](int ms) { run_sampled(sim, imu, command, phase, n, ms); };
    imu.observe(0.0, sim.wrist.fe, sim.wrist.ur);
    imu.sample(0.0);
    run(preroll_ms);
    imu.zero();
    const std::string case_name = fmt::format("{}-{}", name, trial + 1);
    for (int tick_ms = 0; tick_ms <= total_ms; tick_ms += kControlPeriodMs) {
      const double time = tick_ms / 1000.0;
      const auto want = desired(time);
      controller.update(want[0], want[1], imu.fe_deg(), imu.ur_deg(), true, !planar);
      command = controller.command_kpa;
      std::vector<Cell> row{case_name, time};
      // The Arduino prints its float pressures with Serial.print's two decimals.
      for (const double c : command) row.emplace_back(quantise(c, 100.0));
      row.emplace_back(imu.fe_deg());
      row.emplace_back(imu.ur_deg());
      for (std::size_t i = 0; i < 4; ++i)
        row.emplace_back(read_pressure_monitor_kpa(s.regulators[i].monitor_kpa(), s.noisy ? &monitor : nullptr));
      t.rows.push_back(std::move(row));
      run(kControlPeriodMs);
    }
  }
  const std::array<double, 4> off{};
  for (int k = 0; k < 2000; ++k) sim.step(off);
  return t;
}

}  // namespace softwrist::independent
