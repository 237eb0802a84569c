// `softwrist bench bridge`: what the bridge adds to each 14 ms control cycle, measured against the device emulator
// on a pseudo-terminal in this process (one clock for both ends):
//   host_overhead    the controller's side: reading the latest IMU data, the safety checks, formatting and writing
//                    the command (the time command_pressures_kpa + read_angles take);
//   command_latency  from the command's write on the host to the device accepting it (the link and the device's
//                    loop of 1 ms);
//   reading_age      how old the IMU data is when the controller reads it (the 100 Hz data period bounds it).
// A USB serial link to an Uno adds its own transfer time (~50 bytes at 115200 baud: 4 ms) on top of the link here.

#include <algorithm>
#include <chrono>
#include <map>
#include <mutex>
#include <numeric>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bridge/bridge_plant.h"
#include "bridge_apps/device_emulator.h"
#include "cli/arguments.h"
#include "cli/bridge_commands.h"

namespace softwrist::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct BridgeBenchOptions {
  std::string model = "models/rom_device.json";
  int cycles = 700;  // 9.8 s of 14 ms cycles
  bool json = false;
};

struct Spread {
  double mean = 0.0, p50 = 0.0, p99 = 0.0, max = 0.0;
};

Spread spread_of(std::vector<double> v) {
  Spread s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  s.p50 = v[v.size() / 2];
  s.p99 = v[std::min(v.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(v.size())))];
  s.max = v.back();
  return s;
}

nlohmann::json to_json(const Spread& s) { return {{"mean", s.mean}, {"p50", s.p50}, {"p99", s.p99}, {"max", s.max}}; }

constexpr double kPeriod = 0.014;  // the paper's loop (Section Control system)

// The host's side of each cycle.
struct CycleTimes {
  std::vector<double> overhead_us, age_ms;
  std::map<std::uint16_t, Clock::time_point> sent;  // S packets by sequence number
};

// One session of `cycles` control cycles on `plant`, each a reading and a command as a controller would.
CycleTimes time_cycles(bridge::BridgePlant& plant, int cycles) {
  CycleTimes times;
  plant.start_session();
  const double start = plant.time_s();
  for (int k = 0; k < cycles; ++k) {
    const Clock::time_point t0 = Clock::now();
    const control::ImuReading reading = plant.read_angles();
    times.age_ms.push_back(1000.0 * (plant.time_s() - reading.time_s));
    const std::uint16_t seq = plant.next_seq();
    const double phase = (k / 70) % 2 == 0 ? 30.0 : 10.0;  // a slow square wave, as a controller might ask
    plant.command_pressures_kpa({phase, 40.0 - phase, 0.0, 0.0});
    const Clock::time_point t1 = Clock::now();
    times.overhead_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    times.sent[seq] = t1;
    plant.wait_until(start + (k + 1) * kPeriod);
  }
  plant.end_session();
  plant.wait_until(plant.time_s() + 0.05);
  return times;
}

// From each command's write to the device accepting it, for the commands it accepted.
std::vector<double> command_latencies_ms(const std::map<std::uint16_t, Clock::time_point>& sent,
                                         const std::map<std::uint16_t, Clock::time_point>& accepted,
                                         std::mutex& mutex) {
  std::vector<double> latency_ms;
  std::lock_guard<std::mutex> lock(mutex);
  for (const auto& [seq, when] : sent) {
    const auto it = accepted.find(seq);
    if (it == accepted.end()) continue;
    latency_ms.push_back(std::chrono::duration<double, std::milli>(it->second - when).count());
  }
  return latency_ms;
}

struct BenchReport {
  int cycles = 0;
  Spread overhead, latency, age;
  double added_ms = 0.0;
  std::size_t commands_accepted = 0, commands_sent = 0;
  double max_data_gap_s = 0.0;
  std::uint32_t emulator_max_loop_lag_ms = 0;
};

void print_report_json(const BenchReport& r, std::ostream& out) {
  out << nlohmann::json{{"cycles", r.cycles},
                        {"period_ms", kPeriod * 1000.0},
                        {"host_overhead_us", to_json(r.overhead)},
                        {"command_latency_ms", to_json(r.latency)},
                        {"reading_age_ms", to_json(r.age)},
                        {"added_latency_ms", r.added_ms},
                        {"added_fraction_of_period", r.added_ms / (kPeriod * 1000.0)},
                        {"commands_accepted", r.commands_accepted},
                        {"max_data_gap_ms", 1000.0 * r.max_data_gap_s},
                        {"emulator_max_loop_lag_ms", r.emulator_max_loop_lag_ms}}
             .dump()
      << '\n';
}

void print_report_text(const BenchReport& r, std::ostream& out) {
  out << fmt::format("bridge over a pseudo-terminal to the device emulator, {} cycles of {} ms\n", r.cycles,
                     kPeriod * 1000.0);
  out << fmt::format("  host overhead per cycle  mean {:.1f} us, p99 {:.1f} us, max {:.1f} us\n", r.overhead.mean,
                     r.overhead.p99, r.overhead.max);
  out << fmt::format(
      "  command to device        mean {:.2f} ms, p50 {:.2f}, p99 {:.2f}, max {:.2f} ms ({} of {} "
      "accepted)\n",
      r.latency.mean, r.latency.p50, r.latency.p99, r.latency.max, r.commands_accepted, r.commands_sent);
  out << fmt::format("  IMU reading age          mean {:.2f} ms, p99 {:.2f}, max {:.2f} ms (data every 10 ms)\n",
                     r.age.mean, r.age.p99, r.age.max);
  out << fmt::format("  added per cycle          {:.2f} ms = {:.1f} % of the 14 ms period\n", r.added_ms,
                     100.0 * r.added_ms / (kPeriod * 1000.0));
  out << fmt::format("  longest data gap {:.0f} ms, emulator's longest loop lag {} ms (the watchdog allows 40)\n",
                     1000.0 * r.max_data_gap_s, r.emulator_max_loop_lag_ms);
}

void bench_bridge(const BridgeBenchOptions& options, std::ostream& out) {
  if (options.cycles < 10) throw UsageError("--cycles must be >= 10");
  bridge::EmulatorConfig config;
  config.model = options.model;
  config.gravity = 0.0;
  bridge::DeviceEmulator emulator(config);
  std::mutex mutex;
  std::map<std::uint16_t, Clock::time_point> accepted;  // S packets by sequence number
  emulator.set_packet_observer([&](char type, std::uint16_t seq) {
    if (type != wire::kSetPacket) return;
    std::lock_guard<std::mutex> lock(mutex);
    accepted[seq] = Clock::now();
  });
  bridge::PseudoTerminal pty = bridge::PseudoTerminal::Open();
  bridge::BridgePlant plant(bridge::SerialPort::Open(pty.slave_path));
  std::atomic<bool> stop{false};
  std::thread device([&] { emulator.serve(std::move(pty.master), stop); });

  CycleTimes times;
  try {
    times = time_cycles(plant, options.cycles);
  } catch (...) {
    stop = true;
    device.join();
    throw;
  }
  stop = true;
  device.join();

  const std::vector<double> latency_ms = command_latencies_ms(times.sent, accepted, mutex);
  BenchReport report{.cycles = options.cycles,
                     .overhead = spread_of(times.overhead_us),
                     .latency = spread_of(latency_ms),
                     .age = spread_of(times.age_ms)};
  report.added_ms = report.overhead.mean / 1000.0 + report.latency.mean;
  report.commands_accepted = latency_ms.size();
  report.commands_sent = times.sent.size();
  report.max_data_gap_s = plant.stats().max_data_gap_s;
  report.emulator_max_loop_lag_ms = emulator.stats().max_loop_lag_ms;
  if (options.json) {
    print_report_json(report, out);
  } else {
    print_report_text(report, out);
  }
}

}  // namespace

void add_bridge_bench(CLI::App& bench, std::ostream& out) {
  auto options = std::make_shared<BridgeBenchOptions>();
  auto* command = bench.add_subcommand(
      "bridge", "What the bridge adds to each 14 ms control cycle, against the device emulator on a pseudo-terminal");
  command->add_option("--model", options->model, "Placement file of the emulated device")->check(CLI::ExistingFile);
  command->add_option("--cycles", options->cycles, "Control cycles to time");
  command->add_flag("--json", options->json,
                    "Print {host_overhead_us, command_latency_ms, reading_age_ms (each mean, p50, p99, max), "
                    "added_latency_ms, added_fraction_of_period, ...}");
  command->callback([options, &out] { bench_bridge(*options, out); });
}

}  // namespace softwrist::cli
