// The bridge (bridge/bridge_plant.h, hardware_trial.h) against the device emulator (device_emulator.h) on a
// pseudo-terminal, in real time: a trial without extra effects matches the simulated experiment; every fault the
// issue names (a controller asking for 500 kPa, a stalled host, the link cut, garbage both ways, stale IMUs) ends
// vented within 50 ms of its cause, is never acted on, and leaves a readable log.

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <random>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bridge/bridge_plant.h"
#include "bridge/device_emulator.h"
#include "bridge/hardware_trial.h"
#include "control/paper_controller.h"
#include "control/tracking_loop.h"
#include "experiments/runner.h"
#include "io/text_file.h"
#include "io/subprocess.h"
#include "support/kill_process.h"
#include "support/scratch_dir_test.h"

namespace softwrist::bridge {
namespace {

using ::testing::HasSubstr;

// The issue's bound: every fault ends in the vented state within 50 ms.
constexpr std::uint32_t kVentBoundMs = 50;

EmulatorConfig nominal_config() {
  EmulatorConfig c;
  c.model = SOFTWRIST_SOURCE_DIR "/models/rom_device.json";
  c.gravity = 0.0;  // the hand on the table, as the planar experiments
  return c;
}

// The emulator serving a pseudo-terminal on its own thread for the test's lifetime.
class EmulatedDevice {
 public:
  explicit EmulatedDevice(const EmulatorConfig& config) : emulator_(config) {
    PseudoTerminal pty = PseudoTerminal::Open();
    path_ = pty.slave_path;
    host_.emplace(SerialPort::Open(path_));  // opened before the emulator may close its side
    thread_ = std::thread([this, master = std::move(pty.master)]() mutable { emulator_.serve(std::move(master), stop_); });
  }
  ~EmulatedDevice() {
    stop_ = true;
    thread_.join();
  }
  // The host's end of the link (once).
  SerialPort take_link() {
    SerialPort link = std::move(*host_);
    host_.reset();
    return link;
  }
  EmulatorStats stats() const { return emulator_.stats(); }
  const std::string& path() const { return path_; }
  // Lets the device run on for `ms` (its watchdog acts in its own time).
  static void wait_ms(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }

 private:
  DeviceEmulator emulator_;
  std::string path_;
  std::optional<SerialPort> host_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// Every vent the device recorded came within the bound of its cause; returns the vents.
std::vector<VentEvent> expect_vents_within_bound(const EmulatorStats& stats) {
  for (const VentEvent& v : stats.vents) {
    EXPECT_LE(v.t_ms - v.cause_ms, kVentBoundMs) << v.cause << " at " << v.t_ms << " ms";
  }
  return stats.vents;
}

bool has_vent(const std::vector<VentEvent>& vents, const std::string& cause) {
  for (const VentEvent& v : vents) {
    if (v.cause == cause) return true;
  }
  return false;
}

// Drives a session with a constant command every 14 ms for `seconds`.
void hold(BridgePlant& plant, const control::Pressures& p, double seconds) {
  const double start = plant.time_s();
  for (double t = 0.0; t < seconds; t += 0.014) {
    plant.command_pressures_kpa(p);
    plant.wait_until(start + t + 0.014);
  }
}

TEST(BridgeEmulator, HandshakeGivesTheDevicesLimitsAndTheStricterOnesApply) {
  EmulatorConfig config = nominal_config();
  config.limits.max_dkpa = 1200;  // a device configured below the regulators' 137 kPa
  EmulatedDevice device(config);
  BridgeOptions options;
  options.limits.timeout_ms = 60;  // the host's own would allow more time than the device's
  BridgePlant plant(device.take_link(), options);
  const DeviceInfo info = plant.start_session();
  EXPECT_EQ(info.version, wire::kProtocolVersion);
  EXPECT_EQ(info.limits.max_dkpa, 1200);
  EXPECT_EQ(info.limits.timeout_ms, 40u);
  EXPECT_DOUBLE_EQ(plant.max_pressure_kpa(), 120.0);
  EXPECT_TRUE(plant.read_angles().valid);
  EXPECT_TRUE(plant.device_flags() & wire::kVented);  // a session starts vented
  hold(plant, {50.0, 0.0, 0.0, 0.0}, 0.3);
  EXPECT_NEAR(plant.measured_pressures_kpa()[0], 50.0, 10.0);  // the regulator follows (tau 0.1 s)
  plant.end_session();
  EmulatedDevice::wait_ms(30);
  const std::vector<VentEvent> vents = expect_vents_within_bound(device.stats());
  EXPECT_TRUE(has_vent(vents, "emergency stop"));
}

// The experiment the match test runs both ways: the planar task, shortened.
experiments::ExperimentConfig short_planar_config(const std::filesystem::path& dir) {
  const nlohmann::json json = {
      {"format", "softwrist.experiment/1"},
      {"kind", "tracking"},
      {"model", SOFTWRIST_SOURCE_DIR "/models/rom_device.json"},
      {"hand_supported", true},
      {"pairs", {"fe"}},
      {"trajectory", {{"type", "steps"}, {"levels_fe_deg", {0, -10, 10}}, {"hold_s", 3}}},
      {"controllers", {{{"name", "paper"}}, {{"name", "model_based"}}}},
      {"imu", {{"noise_std_deg", 0}, {"bias_limit_deg", 0}}},  // the emulator's IMUs have no effects either
      {"settle_s", 1},
      {"repetitions", 1}};
  return {.json = json, .base_dir = dir, .source = "short_planar.json", .name = "short_planar"};
}

struct Series {
  std::vector<double> measured_fe, cmd_flexor;
};

std::map<std::string, Series> series_by_controller(const experiments::TrialLog& log) {
  std::map<std::string, Series> out;
  const int c_controller = log.table.column("controller"), c_fe = log.table.column("measured_fe_deg");
  const int c_cmd = log.table.column("cmd_flexor_kpa");
  for (std::size_t r = 0; r < log.table.row_count(); ++r) {
    Series& s = out[log.table.cell(r, c_controller)];
    s.measured_fe.push_back(log.table.number(r, c_fe));
    s.cmd_flexor.push_back(log.table.number(r, c_cmd));
  }
  return out;
}

class BridgeTrial : public testing::ScratchDirTest {};

// The same controllers on the simulation and through the bridge against an emulator without extra effects: the
// logs match to within the timing of a real-time link (the command reaches the device up to a millisecond late,
// the IMU data is up to 10 ms old), far inside the tracking error itself.
TEST_F(BridgeTrial, MatchesTheSimulatedExperimentWhenTheEmulatorHasNoExtraEffects) {
  const experiments::ExperimentConfig config = short_planar_config(dir_);
  experiments::run_experiment(config, {.out = dir_ / "sim", .jobs = 1});
  // An 18 s real-time trial: a stall of this process or the emulator's thread beyond the 40 ms watchdog (a busy
  // shared machine; seen once in CI) ends it vented, the safety rules doing their job. The comparison needs a trial
  // without one, so such a trial is run once more; any other fault fails at once.
  std::unique_ptr<EmulatedDevice> device;
  TrialResult result;
  for (int attempt = 0; attempt < 2; ++attempt) {
    device = std::make_unique<EmulatedDevice>(nominal_config());
    BridgePlant plant(device->take_link());
    result = run_trial(config, plant, {.out = dir_ / "hw", .overwrite = true});
    const bool stalled = result.fault && (result.fault->find("watchdog") != std::string::npos ||
                                          result.fault->find("no valid data") != std::string::npos);
    if (!stalled) break;
    std::cerr << "attempt " << attempt + 1 << " ended by a real-time stall: " << *result.fault << "\n";
  }
  ASSERT_FALSE(result.fault) << *result.fault;
  EXPECT_EQ(result.runs_completed, 2);

  const experiments::TrialLog sim = experiments::read_log(dir_ / "sim", "trials");
  const experiments::TrialLog hw = experiments::read_log(dir_ / "hw", "trials");
  EXPECT_EQ(hw.header.source, "hardware");
  EXPECT_EQ(hw.header.config_hash, sim.header.config_hash);
  EXPECT_EQ(hw.header.model_hash, sim.header.model_hash);
  EXPECT_GE(hw.table.find_column("p_flexor_kpa"), 0);
  EXPECT_LT(hw.table.find_column("true_fe_deg"), 0);  // no ground truth on a device
  const auto sim_series = series_by_controller(sim), hw_series = series_by_controller(hw);
  for (const char* name : {"paper", "model_based"}) {
    const Series& a = sim_series.at(name);
    const Series& b = hw_series.at(name);
    ASSERT_EQ(a.measured_fe.size(), b.measured_fe.size()) << name;
    double sum = 0.0, worst = 0.0, worst_cmd = 0.0;
    for (std::size_t i = 0; i < a.measured_fe.size(); ++i) {
      const double d = a.measured_fe[i] - b.measured_fe[i];
      sum += d * d;
      worst = std::max(worst, std::abs(d));
      worst_cmd = std::max(worst_cmd, std::abs(a.cmd_flexor[i] - b.cmd_flexor[i]));
    }
    // Measured here: RMS 0.07 / 0.14 deg, worst 1.0 / 0.8 deg (paper / model-based); the steps are 10 and 20 deg.
    EXPECT_LT(std::sqrt(sum / static_cast<double>(a.measured_fe.size())), 0.5) << name;
    EXPECT_LT(worst, 2.5) << name;
    EXPECT_LT(worst_cmd, 3.0) << name;
  }
  const nlohmann::json sim_summary = nlohmann::json::parse(io::read_text_file(dir_ / "sim" / "summary.json"));
  for (std::size_t c = 0; c < 2; ++c) {
    const nlohmann::json& a = sim_summary["controllers"][c];
    const nlohmann::json& b = result.summary["controllers"][c];
    EXPECT_NEAR(a["rmse_fe_deg"].get<double>(), b["rmse_fe_deg"].get<double>(), 0.25) << a["controller"];
    for (std::size_t s = 0; s < a["steps"].size(); ++s) {
      const nlohmann::json &rise_a = a["steps"][s]["rise_time_s"], &rise_b = b["steps"][s]["rise_time_s"];
      ASSERT_EQ(rise_a.is_null(), rise_b.is_null());  // a step not reached in one is not reached in the other
      if (!rise_a.is_null()) {
        EXPECT_NEAR(rise_a.get<double>(), rise_b.get<double>(), 0.05);
      }
      EXPECT_NEAR(a["steps"][s]["overshoot_pct"].get<double>(), b["steps"][s]["overshoot_pct"].get<double>(), 3.0);
    }
  }
  // Between runs and at the end the device vented on the host's emergency stop, at once.
  const std::vector<VentEvent> vents = expect_vents_within_bound(device->stats());
  EXPECT_TRUE(has_vent(vents, "emergency stop") || has_vent(vents, "zero command"));
  EXPECT_EQ(device->stats().packets_rejected, 0);
  EXPECT_LE(device->stats().max_output_dkpa, 1370);
}

// A controller that asks for 500 kPa half a second in.
class RunawayController final : public control::Controller {
 public:
  std::string name() const override { return "runaway"; }
  double period_s() const override { return 0.014; }
  void reset() override {}
  control::Pressures command(double t, const control::Reference&, const control::ImuReading&) override {
    return {t < 0.5 ? 20.0 : 500.0, 0.0, 0.0, 0.0};
  }
};

TEST(BridgeFaults, AControllerAskingFor500KpaIsStoppedAndVentedNotClamped) {
  EmulatedDevice device(nominal_config());
  BridgePlant plant(device.take_link());
  plant.start_session();
  RunawayController runaway;
  const control::StepTrajectory hold_still({{0.0, 0.0}}, 2.0);
  control::TrackingOptions options;
  options.out_of_range = control::TrackingOptions::OutOfRange::kStop;
  EXPECT_THAT([&] { control::run_tracking(plant, runaway, hold_still, options, nullptr); },
              ::testing::ThrowsMessage<control::ControllerFault>(HasSubstr("500 kPa on the flexor")));
  EmulatedDevice::wait_ms(20);
  const EmulatorStats stats = device.stats();
  EXPECT_LE(stats.max_output_dkpa, 200);  // the device never saw more than the 20 kPa before
  const std::vector<VentEvent> vents = expect_vents_within_bound(stats);
  EXPECT_TRUE(has_vent(vents, "zero command"));
  // The plant refuses such a command itself too, with nothing sent, and vents.
  BridgePlant& p = plant;
  p.end_session();
  EXPECT_THAT([&] { p.command_pressures_kpa({500.0, 0.0, 0.0, 0.0}); },
              ::testing::ThrowsMessage<std::logic_error>(HasSubstr("outside a session")));
  p.start_session();
  EXPECT_THAT([&] { p.command_pressures_kpa({500.0, 0.0, 0.0, 0.0}); },
              ::testing::ThrowsMessage<BridgeFault>(HasSubstr("500 kPa for the flexor")));
  EXPECT_FALSE(p.in_session());
}

TEST(BridgeFaults, TheDeviceClampsAndRejectsWhatAHostSendsWrong) {
  EmulatedDevice device(nominal_config());
  SerialPort raw = device.take_link();
  const auto send = [&](int seq, char type, std::vector<int32_t> fields) {
    wire::Packet p{};
    p.type = type;
    p.seq = static_cast<uint16_t>(seq);
    p.count = static_cast<uint8_t>(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) p.fields[i] = fields[i];
    char buffer[wire::kMaxLine + 2];
    raw.write_all(buffer, wire::format_packet(p, buffer, sizeof buffer));
  };
  send(1, 'H', {wire::kProtocolVersion});
  for (int k = 0; k < 20; ++k) {  // 5000 dkPa = 500 kPa, bypassing the host's checks
    send(2 + k, 'S', {5000, 0, 0, 0});
    EmulatedDevice::wait_ms(10);
  }
  const std::string junk = "S 40 1370 1370 1370 1370 *00\nD 1 2 3\n\x01\xff garbage\n";
  raw.write_all(junk.data(), junk.size());  // a bad checksum, a device packet, noise
  send(10, 'S', {1370, 1370, 1370, 1370});  // valid checksum, stale sequence number
  EmulatedDevice::wait_ms(100);             // the watchdog vents 40 ms after the last valid command
  const EmulatorStats stats = device.stats();
  EXPECT_EQ(stats.max_output_dkpa, 1370);
  EXPECT_GE(stats.packets_rejected, 4);
  const std::vector<VentEvent> vents = expect_vents_within_bound(stats);
  ASSERT_FALSE(vents.empty());
  EXPECT_EQ(vents.back().cause, "watchdog: no command");  // not acted on: the stale packet did not feed the watchdog
}

TEST(BridgeFaults, AStalledHostIsVentedByTheDeviceAndFindsItVentedWhenItWakes) {
  EmulatedDevice device(nominal_config());
  BridgePlant plant(device.take_link());
  plant.start_session();
  hold(plant, {40.0, 0.0, 0.0, 0.0}, 0.5);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the controller's process stalls
  EXPECT_THAT([&] { plant.command_pressures_kpa({40.0, 0.0, 0.0, 0.0}); },
              ::testing::ThrowsMessage<BridgeFault>(HasSubstr("watchdog")));
  const std::vector<VentEvent> vents = expect_vents_within_bound(device.stats());
  EXPECT_TRUE(has_vent(vents, "watchdog: no command"));
  EXPECT_LE(device.stats().max_output_dkpa, 400);
}

TEST(BridgeFaults, TheLinkCutIsALinkFaultAndTheDeviceVentsOnItsOwn) {
  EmulatorConfig config = nominal_config();
  config.faults.link_cut_at_s = 0.8;
  EmulatedDevice device(config);
  BridgePlant plant(device.take_link());
  plant.start_session();
  EXPECT_THAT([&] { hold(plant, {40.0, 0.0, 0.0, 0.0}, 3.0); },
              ::testing::ThrowsMessage<BridgeFault>(HasSubstr("link")));
  EmulatedDevice::wait_ms(100);
  const EmulatorStats stats = device.stats();
  EXPECT_GT(stats.fault_injected_ms[2], 0u);
  const std::vector<VentEvent> vents = expect_vents_within_bound(stats);
  EXPECT_TRUE(has_vent(vents, "watchdog: no command"));
}

TEST(BridgeFaults, StaleImusVentWithinTheBoundAndTheHostSaysWhy) {
  EmulatorConfig config = nominal_config();
  config.faults.imu_stale_at_s = 0.8;
  EmulatedDevice device(config);
  BridgePlant plant(device.take_link());
  plant.start_session();
  EXPECT_THAT([&] { hold(plant, {40.0, 0.0, 0.0, 0.0}, 3.0); },
              ::testing::ThrowsMessage<BridgeFault>(HasSubstr("IMU")));
  EmulatedDevice::wait_ms(50);
  const std::vector<VentEvent> vents = expect_vents_within_bound(device.stats());
  EXPECT_TRUE(has_vent(vents, "watchdog: no IMU") || has_vent(vents, "emergency stop"));
}

TEST(BridgeFaults, GarbageFromTheDeviceIsCountedAndNeverActedOn) {
  EmulatorConfig config = nominal_config();
  config.faults.garbage_at_s = 0.5;
  config.faults.garbage_bytes = 500;
  EmulatedDevice device(config);
  BridgePlant plant(device.take_link());
  plant.start_session();
  hold(plant, {30.0, 0.0, 0.0, 0.0}, 1.5);  // the session survives a short burst
  EXPECT_GT(plant.stats().garbled_from_device + plant.stats().overlong_lines + plant.stats().out_of_sequence, 0);
  EXPECT_TRUE(plant.read_angles().valid);
  plant.end_session();
  EmulatedDevice::wait_ms(30);
  expect_vents_within_bound(device.stats());
}

// A trial that a fault ends keeps every row measured before it and says what happened beside the log.
TEST_F(BridgeTrial, AFaultEndsTheTrialVentedWithAReadableLog) {
  EmulatorConfig config = nominal_config();
  config.faults.imu_stale_at_s = 4.0;  // during the first run (1 s vented pause, then the steps)
  EmulatedDevice device(config);
  BridgePlant plant(device.take_link());
  const TrialResult result = run_trial(short_planar_config(dir_), plant, {.out = dir_ / "hw"});
  ASSERT_TRUE(result.fault);
  EXPECT_THAT(*result.fault, HasSubstr("IMU"));
  EXPECT_EQ(result.runs_completed, 0);
  const experiments::TrialLog log = experiments::read_log(dir_ / "hw", "trials");
  EXPECT_GT(log.table.row_count(), 100u);  // about 2.5 s of rows at 14 ms
  const nlohmann::json record = nlohmann::json::parse(io::read_text_file(dir_ / "hw" / "bridge.json"));
  EXPECT_THAT(record["fault"].get<std::string>(), HasSubstr("IMU"));
  EXPECT_FALSE(record["runs"][0]["completed"].get<bool>());
  EmulatedDevice::wait_ms(30);
  const std::vector<VentEvent> vents = expect_vents_within_bound(device.stats());
  EXPECT_FALSE(vents.empty());
  // A second trial into the same directory is refused: a measured log is never overwritten by accident.
  EXPECT_THAT([&] { run_trial(short_planar_config(dir_), plant, {.out = dir_ / "hw"}); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("holds a trial log already")));
}

// `softwrist trial` killed (SIGKILL) at a random moment of its first run: the device vents on its own within 50 ms
// of the last command, every row written before the kill reads back, and running into the directory again says
// how to re-run.
TEST_F(BridgeTrial, AKilledTrialLeavesTheDeviceVentedAndItsRowsReadable) {
  EmulatedDevice device(nominal_config());
  const std::filesystem::path config = dir_ / "short_planar.json";
  std::ofstream(config) << short_planar_config(dir_).json.dump();
  const std::vector<std::string> trial = {SOFTWRIST_BINARY, "trial", config.string(), "--device", device.path(),
                                          "--out", (dir_ / "hw").string(), "--rest-s", "0.5"};
  // During the first run's steps: after the start, the 0.5 s rest and the 1 s settling, before its 9 s end.
  std::mt19937 rng(std::random_device{}());
  const auto delay = std::chrono::milliseconds(std::uniform_int_distribution<int>(2500, 7000)(rng));
  SCOPED_TRACE("killed after " + std::to_string(delay.count()) + " ms");
  ASSERT_TRUE(testing::start_and_kill(trial, delay));
  EmulatedDevice::wait_ms(100);

  const EmulatorStats stats = device.stats();
  ASSERT_FALSE(stats.vents.empty());
  const VentEvent& last = stats.vents.back();
  EXPECT_EQ(last.cause, "watchdog: no command");
  EXPECT_LE(last.t_ms - last.cause_ms, kVentBoundMs);

  const experiments::TrialLog log = experiments::read_log(dir_ / "hw", "trials");
  EXPECT_GT(log.table.row_count(), 50u);
  for (std::size_t r = 0; r < log.table.row_count(); ++r) {
    for (std::size_t c = 0; c < log.table.header().size(); ++c) {
      if (log.table.header()[c] != "controller") (void)log.table.number(r, static_cast<int>(c));
    }
  }
  const int code = io::run_process(trial, {.stdout_file = dir_ / "again.out", .stderr_file = dir_ / "again.err"});
  EXPECT_EQ(code, 1);
  EXPECT_THAT(io::read_text_file(dir_ / "again.err"), HasSubstr("holds a trial log already"));
  EXPECT_THAT(io::read_text_file(dir_ / "again.err"), HasSubstr("--overwrite"));
}

TEST(EmulatorConfig, ReadsEffectsAndFaultsAndNamesBadFields) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "softwrist_emulator_config_test";
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& text) {
    std::ofstream(dir / "emulator.json") << text;
    return dir / "emulator.json";
  };
  const EmulatorConfig c = load_emulator_config(write(R"({"format": "softwrist.emulator/1", "model": "device.json",
      "hand_supported": true, "effects": {"mount_stretch": {"K1_n_per_cm2": 15, "K2_n_per_cm2": 300},
      "regulator_lag": {"time_constant_s": 0.25, "dead_time_s": 0.03},
      "imu": {"noise_std_deg": 0.3, "bias_fe_deg": 1.5, "latency_s": 0.02}}, "faults": {"link_cut_at_s": 5}})"));
  EXPECT_EQ(c.model, dir / "device.json");
  EXPECT_EQ(c.gravity, 0.0);
  ASSERT_TRUE(c.effects.mount_stiffness);
  EXPECT_DOUBLE_EQ(c.effects.mount_stiffness->forearm, 15e4);  // N/cm^2 -> N/m^2
  EXPECT_DOUBLE_EQ(*c.effects.regulator_time_constant_s, 0.25);
  EXPECT_DOUBLE_EQ(c.effects.imu_bias_fe_deg, 1.5);
  EXPECT_DOUBLE_EQ(c.faults.link_cut_at_s, 5.0);
  EXPECT_LT(c.faults.imu_stale_at_s, 0.0);
  EXPECT_THAT([&] { load_emulator_config(write(R"({"format": "softwrist.emulator/1", "model": "d.json",
      "effects": {"regulator_lag": {"dead_time_s": -1}}})")); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("dead_time_s")));
  EXPECT_THAT([&] { load_emulator_config(write(R"({"format": "softwrist.emulator/1", "model": "d.json",
      "effects": {"imu": {"noise": 1}}})")); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("noise")));
  EXPECT_THAT([&] { load_emulator_config(write(R"({"format": "softwrist.experiment/1", "model": "d.json"})")); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("format")));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace softwrist::bridge
