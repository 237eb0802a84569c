#include "bridge_apps/soak.h"

#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "bridge/bridge_plant.h"
#include "bridge_apps/fault_relay.h"
#include "bridge_apps/hardware_trial.h"
#include "bridge_apps/lockstep_link.h"
#include "experiments/runner.h"
#include "experiments/trial_log.h"
#include "io/json_reader.h"
#include "io/text_file.h"

namespace softwrist::bridge {
namespace {

namespace fs = std::filesystem;
using SteadyTime = std::chrono::steady_clock;

double seconds_between(SteadyTime::time_point from, SteadyTime::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

MemorySample sample_memory(double t_s) {
  const struct mallinfo2 info = mallinfo2();
  MemorySample m{.t_s = t_s, .heap_bytes = info.uordblks + info.hblkhd};
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0, resident = 0;
  if (statm >> pages >> resident) m.resident_bytes = resident * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  return m;
}

// What is wrong with a trial's log and record, or "" when the log reads back whole.
std::string check_trial_log(const fs::path& dir, long* rows) {
  try {
    const experiments::TrialLog log = experiments::read_log(dir, experiments::kTrialLogName);
    *rows = static_cast<long>(log.table.row_count());
    if (log.unfinished_line != 0) return fmt::format("line {} cut short", log.unfinished_line);
    const auto record = io::parse_json(io::read_text_file(dir / "bridge.json"), (dir / "bridge.json").string());
    long counted = 0;
    for (const auto& run : record.at("runs")) counted += run.at("rows").get<long>();
    if (counted != *rows) return fmt::format("{} rows in the log, {} counted in bridge.json", *rows, counted);
    const int c_case = log.table.column("case"), c_t = log.table.column("t_s");
    std::map<std::string, double> last_t;
    for (std::size_t r = 0; r < log.table.row_count(); ++r) {
      const double t = log.table.number(r, c_t);
      auto [it, first] = last_t.try_emplace(log.table.cell(r, c_case), t);
      if (!first && !(t > it->second)) return fmt::format("line {}: time does not increase", log.table.line_of(r));
      it->second = t;
    }
    return "";
  } catch (const std::exception& e) {
    return e.what();
  }
}

// Hardware trials back to back until `stop` is set. `open` gives a plant on the link as it now is, or nothing
// while the cable is out (`wait` then lets 10 ms pass); `elapsed` is the soak's clock.
void run_trials(const experiments::ExperimentConfig& config, const SoakOptions& options, const std::atomic<bool>& stop,
                const std::function<std::unique_ptr<BridgePlant>()>& open, const std::function<void()>& wait,
                const std::function<double()>& elapsed, std::vector<SoakTrial>& trials) {
  for (int index = 1; !stop;) {
    SoakTrial trial{.dir = options.out / fmt::format("trial_{:04d}", index)};
    try {
      const std::unique_ptr<BridgePlant> plant = open();
      if (!plant) {  // the cable is out
        wait();
        continue;
      }
      const TrialResult r =
          run_trial(config, *plant, {.out = trial.dir, .repetitions = 1000000, .overwrite = true, .interrupt = &stop});
      trial.runs_completed = r.runs_completed;
      trial.fault = r.fault.value_or("");
    } catch (const std::runtime_error& e) {  // the link went while opening it
      trial.fault = e.what();
      if (!fs::exists(trial.dir / "trials.json")) continue;
    }
    trial.problem = check_trial_log(trial.dir, &trial.rows);
    if (options.progress) {
      *options.progress << fmt::format("{:7.1f} s  {}: {} rows, ended by: {}\n", elapsed(),
                                       trial.dir.filename().string(), trial.rows,
                                       trial.fault.empty() ? "the end of the soak" : trial.fault)
                        << std::flush;
    }
    trials.push_back(std::move(trial));
    ++index;
  }
}

// Real time: the emulator and the relay on threads, a watch thread that ends the soak and samples memory. The
// device's clock starts at result.emulator.epoch, the relay's at its start: both are put on the soak's clock.
void soak_in_real_time(const experiments::ExperimentConfig& config, const EmulatorConfig& emulator_config,
                       const SoakOptions& options, SoakResult& result, double& device_zero_s) {
  const SteadyTime::time_point start = SteadyTime::now();
  const auto elapsed = [&] { return seconds_between(start, SteadyTime::now()); };
  PseudoTerminal device_link = PseudoTerminal::Open();
  DeviceEmulator emulator(emulator_config);
  std::atomic<bool> stop_emulator{false};
  std::thread emulator_thread([&] { emulator.serve(std::move(device_link.master), stop_emulator); });
  std::atomic<bool> deadline{false};  // ends the trial running at the end of the soak, after its current row
  std::mutex memory_mutex;
  std::thread watch([&] {
    double next_sample = 0.0;
    while (!deadline) {
      const double t = elapsed();
      if (t >= options.duration_s) deadline = true;
      if (t >= next_sample) {
        std::lock_guard lock(memory_mutex);
        result.memory.push_back(sample_memory(t));
        next_sample += options.memory_sample_s;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  const auto join = [&] {
    deadline = true;
    watch.join();
    stop_emulator = true;
    emulator_thread.join();
  };
  try {
    FaultRelay relay(SerialPort::Open(device_link.slave_path), options.faults);
    const auto open = [&]() -> std::unique_ptr<BridgePlant> {
      const std::string path = relay.host_path();
      return path.empty() ? nullptr : std::make_unique<BridgePlant>(SerialPort::Open(path));
    };
    run_trials(
        config, options, deadline, open, [] { std::this_thread::sleep_for(std::chrono::milliseconds(10)); }, elapsed,
        result.trials);
    // Faults of the last moments are still judged: the relay keeps running until the device had time to vent.
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const double relay_zero_s = seconds_between(start, relay.started());
    for (const InjectedFault& f : relay.faults())
      result.faults.push_back({.fault = f, .onset_s = relay_zero_s + f.onset_s});
  } catch (...) {
    join();
    throw;
  }
  join();
  result.duration_s = elapsed();
  result.memory.push_back(sample_memory(result.duration_s));
  result.emulator = emulator.stats();
  device_zero_s = seconds_between(start, result.emulator.epoch);
}

// Simulated time: the lock-step rig, one clock for the device, the line and the host.
void soak_in_simulated_time(const experiments::ExperimentConfig& config, const EmulatorConfig& emulator_config,
                            const SoakOptions& options, SoakResult& result) {
  DeviceEmulator emulator(emulator_config);
  LockstepLink rig(emulator, {.faults = options.faults});
  std::atomic<bool> deadline{false};
  double next_sample = 0.0;
  rig.set_tick_observer([&](std::uint32_t t_ms) {
    const double t = t_ms / 1000.0;
    if (t >= options.duration_s) deadline = true;
    if (t >= next_sample) {
      result.memory.push_back(sample_memory(t));
      next_sample += options.memory_sample_s;
    }
  });
  const auto open = [&]() -> std::unique_ptr<BridgePlant> {
    return rig.cable_in() ? std::make_unique<BridgePlant>(rig.open_host(), rig) : nullptr;
  };
  run_trials(
      config, options, deadline, open, [&] { rig.run_for_ms(10); }, [&] { return rig.now_s(); }, result.trials);
  rig.run_for_ms(200);  // the device has time to vent after the faults of the last moments
  for (const InjectedFault& f : rig.faults()) result.faults.push_back({.fault = f, .onset_s = f.onset_s});
  result.duration_s = rig.now_s();
  result.memory.push_back(sample_memory(result.duration_s));
  result.emulator = emulator.stats();
}

// Each fault against the device's own vent record (`device_zero_s`: the device clock's zero on the soak's), each
// log, the emulator and the pressure limit.
void judge(const SoakOptions& options, const wire::SafetyLimits& limits, double device_zero_s, SoakResult& result) {
  for (std::size_t i = 0; i < result.faults.size(); ++i) {
    FaultOutcome& f = result.faults[i];
    if (f.fault.device_vented_at_onset) {
      f.vent_after_s = 0.0;
      f.vent_cause = "vented already";
      continue;
    }
    // The device's data packets come every 10 ms: a vent up to 10 ms before the onset may not have shown yet.
    const double until = i + 1 < result.faults.size() ? result.faults[i + 1].onset_s : result.duration_s;
    for (const VentEvent& v : result.emulator.vents) {
      const double t = device_zero_s + v.t_ms / 1000.0;
      if (t < f.onset_s - 0.011) continue;
      if (t > until) break;
      f.vent_after_s = std::max(0.0, t - f.onset_s);
      f.vent_cause = v.cause;
      break;
    }
    const std::string what = fmt::format("{} at {:.3f} s", link_fault_name(f.fault.kind), f.onset_s);
    if (!f.vent_after_s) {
      result.failures.push_back(what + ": the device never vented");
    } else if (*f.vent_after_s > options.vent_deadline_s) {
      result.failures.push_back(fmt::format("{}: vented after {:.1f} ms (deadline {:.0f} ms)", what,
                                            1000.0 * *f.vent_after_s, 1000.0 * options.vent_deadline_s));
    }
  }
  for (const SoakTrial& t : result.trials) {
    if (!t.problem.empty()) result.failures.push_back(fmt::format("{}: its log: {}", t.dir.string(), t.problem));
  }
  if (!result.emulator.stopped_by.empty())
    result.failures.push_back("the emulator stopped: " + result.emulator.stopped_by);
  if (result.emulator.max_output_dkpa > limits.max_dkpa) {
    result.failures.push_back(fmt::format("the regulators were given {} dkPa, above the limit {}",
                                          result.emulator.max_output_dkpa, limits.max_dkpa));
  }
}

}  // namespace

SoakResult run_soak(const experiments::ExperimentConfig& config, const EmulatorConfig& emulator_config,
                    const SoakOptions& options) {
  if (!(options.duration_s > 0.0)) throw std::runtime_error("soak: the duration must be > 0 s");
  LineFaults check(options.faults);  // refuses bad fault options before anything starts
  fs::create_directories(options.out);
  SoakResult result{.simulated_time = options.simulated_time};
  double device_zero_s = 0.0;
  if (options.simulated_time) {
    soak_in_simulated_time(config, emulator_config, options, result);
  } else {
    soak_in_real_time(config, emulator_config, options, result, device_zero_s);
  }
  judge(options, emulator_config.limits, device_zero_s, result);
  std::ofstream(options.out / "soak.json") << to_json(result).dump(2) << '\n';
  return result;
}

nlohmann::json to_json(const SoakResult& result) {
  nlohmann::json faults = nlohmann::json::array(), trials = nlohmann::json::array(), memory = nlohmann::json::array();
  double max_vent = 0.0;
  std::map<std::string, int> by_kind;
  for (const FaultOutcome& f : result.faults) {
    faults.push_back(
        {{"kind", link_fault_name(f.fault.kind)},
         {"onset_s", f.onset_s},
         {"duration_s", f.fault.duration_s},
         {"vented_at_onset", f.fault.device_vented_at_onset},
         {"vent_after_ms", f.vent_after_s ? nlohmann::json(1000.0 * *f.vent_after_s) : nlohmann::json(nullptr)},
         {"vent_cause", f.vent_cause}});
    if (f.vent_after_s) max_vent = std::max(max_vent, *f.vent_after_s);
    ++by_kind[link_fault_name(f.fault.kind)];
  }
  long rows = 0;
  for (const SoakTrial& t : result.trials) {
    trials.push_back({{"dir", t.dir.filename().string()},
                      {"rows", t.rows},
                      {"runs_completed", t.runs_completed},
                      {"ended_by", t.fault},
                      {"log_problem", t.problem}});
    rows += t.rows;
  }
  for (const MemorySample& m : result.memory) {
    memory.push_back({{"t_s", m.t_s}, {"heap_bytes", m.heap_bytes}, {"resident_bytes", m.resident_bytes}});
  }
  return {{"passed", result.passed()},
          {"failures", result.failures},
          {"duration_s", result.duration_s},
          {"clock", result.simulated_time ? "simulated" : "real"},
          {"trials", result.trials.size()},
          {"rows", rows},
          {"faults", result.faults.size()},
          {"faults_by_kind", by_kind},
          {"max_vent_after_ms", 1000.0 * max_vent},
          {"device",
           {{"sessions", result.emulator.sessions},
            {"packets_accepted", result.emulator.packets_accepted},
            {"packets_rejected", result.emulator.packets_rejected},
            {"max_output_kpa", result.emulator.max_output_dkpa / 10.0},
            {"max_loop_lag_ms", result.emulator.max_loop_lag_ms}}},
          {"memory", memory},
          {"fault_list", faults},
          {"trial_list", trials}};
}

}  // namespace softwrist::bridge
