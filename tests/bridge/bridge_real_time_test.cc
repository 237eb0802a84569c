// The bridge against the device emulator in real time, over a pseudo-terminal, as `softwrist emulate` and
// `softwrist trial` run: what it does, not how fast. How long this host stalls depends on how busy it is, so the
// emulated device here has a 500 ms watchdog instead of 40 ms (a host-dependent margin, not a property of the
// device), the tests check behaviour (the device ends vented, the host says why, the log reads back) and compare no
// interval against a deadline. The timing rules themselves are checked exactly in simulated time
// (bridge_emulator_test.cc); the real device's timing is the firmware's (firmware/README.md).

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <iterator>
#include <optional>
#include <random>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bridge/bridge_plant.h"
#include "bridge_apps/device_emulator.h"
#include "bridge_apps/soak.h"
#include "experiments/runner.h"
#include "io/subprocess.h"
#include "io/text_file.h"
#include "support/emulator_test_support.h"
#include "support/kill_process.h"
#include "support/scratch_dir_test.h"

namespace softwrist::bridge {
namespace {

using ::testing::HasSubstr;
using testing::hold;
using testing::nominal_emulator_config;
using testing::short_planar_config;

// The emulator serving a pseudo-terminal on its own thread for the test's lifetime.
class EmulatedDevice {
 public:
  explicit EmulatedDevice(const EmulatorConfig& config) : emulator_(config) {
    PseudoTerminal pty = PseudoTerminal::Open();
    path_ = pty.slave_path;
    host_.emplace(SerialPort::Open(path_));  // opened before the emulator may close its side
    thread_ =
        std::thread([this, master = std::move(pty.master)]() mutable { emulator_.serve(std::move(master), stop_); });
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
  // Waits (up to 5 s) until the device is vented and has recorded a vent; returns its record.
  EmulatorStats vented_stats() const {
    for (int k = 0; k < 500; ++k) {
      const EmulatorStats s = emulator_.stats();
      if (s.vented && !s.vents.empty()) return s;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return emulator_.stats();
  }
  const std::string& path() const { return path_; }

 private:
  DeviceEmulator emulator_;
  std::string path_;
  std::optional<SerialPort> host_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// The nominal device with the real-time tests' watchdog (the host's own is given the same).
EmulatorConfig real_time_config() {
  EmulatorConfig c = nominal_emulator_config();
  c.limits.timeout_ms = 500;
  return c;
}

BridgeOptions real_time_options() {
  BridgeOptions o;
  o.limits.timeout_ms = 500;
  return o;
}

TEST(BridgeRealTime, ASessionOverAPseudoTerminalEndsVentedOnTheEmergencyStop) {
  EmulatedDevice device(real_time_config());
  BridgePlant plant(device.take_link(), real_time_options());
  const DeviceInfo info = plant.start_session();
  EXPECT_EQ(info.version, wire::kProtocolVersion);
  hold(plant, {50.0, 0.0, 0.0, 0.0}, 0.3);
  EXPECT_GT(plant.measured_pressures_kpa()[0], 0.0);
  plant.end_session();
  const EmulatorStats stats = device.vented_stats();
  EXPECT_TRUE(stats.vented);
  ASSERT_EQ(stats.vents.size(), 1u);
  EXPECT_EQ(stats.vents[0].cause, "emergency stop");
  EXPECT_LE(stats.max_output_dkpa, 500);
}

TEST(BridgeRealTime, ALinkCutEndsTheSessionAndTheDeviceVentsOnItsOwn) {
  EmulatorConfig config = real_time_config();
  config.faults.link_cut_at_s = 0.5;
  EmulatedDevice device(config);
  BridgePlant plant(device.take_link(), real_time_options());
  plant.start_session();
  EXPECT_THAT(
      [&] {
        hold(plant, {40.0, 0.0, 0.0, 0.0}, 3.0);
      },
      ::testing::ThrowsMessage<BridgeFault>(HasSubstr("link lost")));
  const EmulatorStats stats = device.vented_stats();
  EXPECT_GT(stats.fault_injected_ms[2], 0u);
  EXPECT_TRUE(stats.vented);
  ASSERT_EQ(stats.vents.size(), 1u);
  EXPECT_EQ(stats.vents[0].cause, "watchdog: no command");
}

class BridgeRealTimeTrial : public testing::ScratchDirTest {};

// `softwrist trial` killed (SIGKILL) at a random moment of its first run: the device ends vented on its own, every
// row written before the kill reads back, and running into the directory again says how to re-run.
TEST_F(BridgeRealTimeTrial, AKilledTrialLeavesTheDeviceVentedAndItsRowsReadable) {
  EmulatedDevice device(real_time_config());
  const std::filesystem::path config = dir_ / "short_planar.json";
  std::ofstream(config) << short_planar_config(dir_).json.dump();
  const std::vector<std::string> trial = {
      SOFTWRIST_BINARY,       "trial",    config.string(), "--device",     device.path(), "--out",
      (dir_ / "hw").string(), "--rest-s", "0.5",           "--timeout-ms", "500"};
  // During the first run's steps (about 640 rows of 14 ms), after a random number of rows: a moment chosen by the
  // trial's progress, not by this host's speed.
  std::mt19937 rng(std::random_device{}());
  const std::size_t kill_after_rows = std::uniform_int_distribution<std::size_t>(60, 500)(rng);
  SCOPED_TRACE("killed after " + std::to_string(kill_after_rows) + " rows");
  const auto rows_written = [&] {
    std::ifstream csv(dir_ / "hw" / "trials.csv");
    return static_cast<std::size_t>(std::count(std::istreambuf_iterator<char>(csv), {}, '\n'));
  };
  ASSERT_TRUE(testing::start_and_kill_when(
      trial, [&] { return rows_written() > kill_after_rows; }, std::chrono::seconds(120)));
  EXPECT_GT(rows_written(), kill_after_rows);
  const EmulatorStats stats = device.vented_stats();
  EXPECT_TRUE(stats.vented);
  ASSERT_FALSE(stats.vents.empty());
  EXPECT_EQ(stats.vents.back().cause, "watchdog: no command");  // nobody sent anything after the kill

  const experiments::TrialLog log = experiments::read_log(dir_ / "hw", "trials");
  EXPECT_GE(log.table.row_count(), kill_after_rows);
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

class BridgeRealTimeSoak : public testing::ScratchDirTest {};

// A few seconds of the real-time soak (the emulator and the fault relay on threads, pseudo-terminals): the trials
// run one after another over the broken link and every log reads back whole. How fast each fault vented is this
// host's figure here, not checked (the soak in simulated time checks it exactly: soak_test.cc).
TEST_F(BridgeRealTimeSoak, TrialsOverAFaultyRelayKeepEveryLogWhole) {
  const auto config = experiments::load_experiment_config(SOFTWRIST_SOURCE_DIR "/experiments/planar_rehearsal.json");
  const auto emulator = load_emulator_config(SOFTWRIST_SOURCE_DIR "/experiments/emulator/realistic.json");
  const SoakResult result =
      run_soak(config, emulator, {.duration_s = 8.0, .out = dir_, .faults = {.mean_interval_s = 1.0, .seed = 5}});
  EXPECT_FALSE(result.simulated_time);
  EXPECT_GE(result.faults.size(), 2u);
  ASSERT_GE(result.trials.size(), 2u);
  for (const SoakTrial& t : result.trials) EXPECT_EQ(t.problem, "") << t.dir;
  EXPECT_EQ(result.emulator.stopped_by, "");
  EXPECT_LE(result.emulator.max_output_dkpa, emulator.limits.max_dkpa);
}

}  // namespace
}  // namespace softwrist::bridge
