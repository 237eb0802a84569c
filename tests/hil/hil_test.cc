// The real firmware on a simulated ATmega328P driving the simulated exosuit (src/hil/avr_board.h), in AVR time: the
// planar rehearsal matches the emulator, every fault vents within 50 ms of its cause, the loop and the stack stay
// within their budgets, and the firmware bugs the board found stay fixed.

#include "hil/avr_board.h"
#include "hil/side_by_side.h"

#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>

#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bridge/bridge_plant.h"
#include "bridge/wire_format.h"
#include "bridge_apps/hardware_trial.h"
#include "bridge_apps/lockstep_link.h"
#include "experiments/experiment.h"

namespace softwrist::hil {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kSource = SOFTWRIST_SOURCE_DIR;
const fs::path kFirmware = SOFTWRIST_FIRMWARE_ELF;  // built by the firmware_builds test (a CTest fixture)

bridge::EmulatorConfig nominal_plant() {
  return bridge::load_emulator_config(kSource / "experiments/emulator/nominal.json");
}

// The board's first vent at or after `from_ms`, in AVR milliseconds; -1 when none.
long first_vent_from(const BoardStats& stats, std::uint32_t from_ms) {
  for (std::uint32_t t : stats.vent_ms) {
    if (t >= from_ms) return static_cast<long>(t);
  }
  return -1;
}

// A board, the rig around it and a host in session, commanding `kpa` to the flexor every 14 ms (the controllers'
// period) for `ms` milliseconds of AVR time.
struct Session {
  Session() : board(kFirmware, nominal_plant()), rig(board), host(rig.open_host(), rig, {}) { host.start_session(); }
  void command_for(double kpa, int ms) {
    const double until = rig.now_s() + ms / 1000.0;
    while (rig.now_s() < until) {
      host.command_pressures_kpa({kpa, 0.0, 0.0, 0.0});
      last_command_ms = rig.now_ms();
      host.wait_until(rig.now_s() + 0.014);
    }
  }
  long vent_after(std::uint32_t from_ms) const { return first_vent_from(board.stats(), from_ms); }
  AvrBoard board;
  bridge::LockstepLink rig;
  bridge::BridgePlant host;
  std::uint32_t last_command_ms = 0;
};

TEST(AvrBoard, RefusesAFileThatIsNotAvrFirmware) {
  try {
    AvrBoard board(kSource / "README.md", nominal_plant());
    FAIL() << "loaded a README as firmware";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("README.md: cannot read as AVR firmware"));
  }
}

// The planar rehearsal with the paper's controller, through the firmware and on the emulator (the firmware's rules
// in C++): the measured angles agree within the IMU's resolution and the PWM's 8 bits (measured: RMS 0.093 deg, 0.21
// before the emulator had the board's RC filter); and the loop's worst pass at 16 MHz with both IMUs and all four ADCs
// read, and the stack, stay within budget.
TEST(FirmwareInTheLoop, PlanarRehearsalMatchesTheEmulatorWithinBudgets) {
  const fs::path dir = fs::temp_directory_path() / ("softwrist_hil_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto config = experiments::load_experiment_config(kSource / "experiments/planar_rehearsal.json");
  SideBySide run;
  ASSERT_NO_THROW(run = run_side_by_side(config, nominal_plant(), kFirmware,
                                         {.controllers = {"paper"}, .repetitions = 1}, dir));  // no fault
  const AngleDifference& d = run.angles;
  EXPECT_GT(d.rows, 1000U);
  EXPECT_LT(d.rms_deg, 0.5);
  // The steps' responses: rise times within five control periods, overshoots within a percentage point (measured:
  // 28 ms apart on the first step, the same on the second). Issue 21 asked one period, which this experiment cannot
  // resolve: the 90 % crossing falls in the controller's slow creep, where the emulator's own rise time moves by a
  // period for a 0.01 deg offset of its angles and by six for a 20 ms latency (docs/hil.md, measured).
  const auto steps = [](const fs::path& run_dir) {
    return nlohmann::json::parse(std::ifstream(run_dir / "summary.json"))["controllers"][0]["steps"];
  };
  const nlohmann::json hil_steps = steps(run.firmware_dir), emulator_steps = steps(run.emulator_dir);
  ASSERT_EQ(hil_steps.size(), emulator_steps.size());
  int compared = 0;
  for (std::size_t k = 0; k < hil_steps.size(); ++k) {
    const nlohmann::json &a = hil_steps[k], &b = emulator_steps[k];
    if (!a["rise_time_s"].is_number() || !b["rise_time_s"].is_number()) continue;
    EXPECT_NEAR(a["rise_time_s"].get<double>(), b["rise_time_s"].get<double>(), 5 * 0.014) << a.dump();
    EXPECT_NEAR(a["overshoot_pct"].get<double>(), b["overshoot_pct"].get<double>(), 1.0) << a.dump();
    ++compared;
  }
  EXPECT_GE(compared, 2);
  const BoardStats& s = run.board;
  EXPECT_EQ(s.resets, 0);
  EXPECT_GT(s.i2c_reads, 3000);  // two IMUs at 100 Hz for 17 s
  // Budgets (docs/hil.md): a pass of the loop under 4.5 ms (measured 3.69 ms, the pass that reads both IMUs and sends a
  // data packet; it was 5.2 ms before the firmware stopped dividing in 64 bits; the watchdog's 40 ms plus a pass must
  // stay within the 50 ms vent rule), a mean pass under 0.5 ms (measured 0.20; 0.91 before the PWM was rewritten only
  // on change), 512 bytes of stack never touched, at most 1 KiB of the 2 KiB of RAM static, and the firmware within the
  // Uno's 31.5 KiB of flash.
  EXPECT_LT(s.loop_max_cycles, 4500U * 16U);
  ASSERT_GT(s.loops, 0);
  EXPECT_LT(s.loop_cycles_total / static_cast<std::uint64_t>(s.loops), 500U * 16U);
  EXPECT_GE(s.stack_headroom_bytes, 512);
  const FirmwareSize size = firmware_size(kFirmware);
  EXPECT_LE(size.flash_bytes, 32256);
  EXPECT_LE(size.ram_bytes, 1024);
  fs::remove_all(dir);
}

// Regressions (found by this board): the firmware truncated pressure to PWM, setting a regulator up to one PWM step
// (137/255 = 0.54 kPa) low (50.5 kPa came out as 49.96), and scaled timer 0's fast-PWM pins (5, 6: extensor, ulnar)
// as the phase-correct ones, up to a step high. Each muscle's regulator is now set within half a PWM step. The
// pressure the host is told stays within one ADC step (0.13 kPa) and the wire's 0.05 kPa of what the regulator holds
// (the monitors' truncating conversion, also fixed, met that too: that part is a check, not a regression test).
TEST(FirmwareInTheLoop, PwmSetsTheNearestStepOnEveryTimer) {
  for (std::size_t muscle = 0; muscle < 4; ++muscle) {
    Session s;
    const double kpa = muscle % 2 == 0 ? 50.5 : 20.2;
    control::Pressures command{};
    command[muscle] = kpa;
    const double until = s.rig.now_s() + 1.0;  // the regulator settles (0.1 s time constant)
    while (s.rig.now_s() < until) {
      s.host.command_pressures_kpa(command);
      s.host.wait_until(s.rig.now_s() + 0.014);
    }
    EXPECT_NEAR(s.board.setpoints_kpa()[muscle], kpa, 0.5 * 137.0 / 255.0) << control::kMuscleNames[muscle];
    EXPECT_NEAR(s.host.measured_pressures_kpa()[muscle], s.board.regulated_pressures_kpa()[muscle],
                137.0 / 1023.0 + 0.05)
        << control::kMuscleNames[muscle];
  }
}

// A host that stops commanding (stalled, or its cable pulled): the firmware's 40 ms watchdog vents.
TEST(FirmwareInTheLoop, StalledHostVentsWithin50ms) {
  Session s;
  s.command_for(80.0, 300);
  ASSERT_FALSE(s.board.stats().vented);
  s.rig.run_for_ms(200);
  const long vent = s.vent_after(s.last_command_ms);
  ASSERT_GE(vent, 0);
  EXPECT_LE(vent - static_cast<long>(s.last_command_ms), 50);
}

TEST(FirmwareInTheLoop, OpenedSafetySwitchVentsWithin50msWhateverTheHostSays) {
  Session s;
  s.command_for(80.0, 300);
  const std::uint32_t opened = s.rig.now_ms();
  s.board.set_safety_switch_open(true);
  s.command_for(80.0, 200);
  const long vent = s.vent_after(opened);
  ASSERT_GE(vent, 0);
  EXPECT_LE(vent - static_cast<long>(opened), 50);
  EXPECT_TRUE(s.board.stats().vented);
}

// The hand IMU fails (`fail` on the board) while the host commands 80 kPa; the host keeps commanding for `ms` until it
// stops on the device's IMU fault flag. Returns the milliseconds from the fault to the vent (-1: no vent).
long ms_from_imu_fault_to_vent(Session& s, void (AvrBoard::*fail)(int, bool), int ms) {
  s.command_for(80.0, 300);
  const std::uint32_t fault = s.rig.now_ms();
  (s.board.*fail)(1, true);
  try {
    s.command_for(80.0, ms);
  } catch (const bridge::BridgeFault&) {
  }
  const long vent = s.vent_after(fault);
  return vent < 0 ? -1 : vent - static_cast<long>(fault);
}

// An IMU that stops answering on the bus (a loose I2C cable): no valid reading, the gate vents.
TEST(FirmwareInTheLoop, SilentImuVentsWithin50ms) {
  Session s;
  const long vent_ms = ms_from_imu_fault_to_vent(s, &AvrBoard::set_imu_silent, 200);
  ASSERT_GE(vent_ms, 0);
  EXPECT_LE(vent_ms, 50);
  EXPECT_EQ(s.board.stats().resets, 0);  // a NACK is an error the Wire library returns, not a hang
}

// The IMU answers again (the cable pushed back in): the firmware puts it back into fusion mode over 45 ms without
// holding its loop (as two delay()s it would have outlasted the hardware watchdog's 32 ms and reset the board), and
// the next session runs.
TEST(FirmwareInTheLoop, ImuThatComesBackStartsAgainWithoutAReset) {
  Session s;
  ASSERT_GE(ms_from_imu_fault_to_vent(s, &AvrBoard::set_imu_silent, 200), 0);
  s.board.set_imu_silent(1, false);
  s.rig.run_for_ms(200);
  ASSERT_NO_THROW(s.host.start_session());
  s.command_for(30.0, 500);
  EXPECT_NEAR(s.board.setpoints_kpa()[0], 30.0, 1.0);
  EXPECT_EQ(s.board.stats().resets, 0);
  EXPECT_LT(s.board.stats().loop_max_cycles, 4500U * 16U);
}

// The host's end of the line written to directly, as a broken or hostile host would: packets the firmware must
// check, not trust.
struct RawHost {
  RawHost() : board(kFirmware, nominal_plant()), rig(board), link(rig.open_host()) {}
  void send(char type, std::initializer_list<int32_t> fields) {
    wire::Packet p{};
    p.type = type;
    p.seq = seq++;
    p.count = static_cast<uint8_t>(fields.size());
    int i = 0;
    for (int32_t f : fields) p.fields[i++] = f;
    char buffer[wire::kMaxLine + 2];
    const std::size_t n = wire::format_packet(p, buffer, sizeof buffer);
    link->write_all(buffer, n);
  }
  // Commands `dkpa` to the flexor every 14 ms for `ms`, reading (and dropping) what the device sends.
  void command_for(int32_t dkpa, int ms) {
    char sink[512];
    for (int t = 0; t < ms; t += 14) {
      send(wire::kSetPacket, {dkpa, 0, 0, 0});
      last_command_ms = rig.now_ms();
      while (link->read_some(sink, sizeof sink, 0) > 0) {
      }
      rig.run_for_ms(14);
    }
  }
  AvrBoard board;
  bridge::LockstepLink rig;
  std::unique_ptr<bridge::Link> link;
  std::uint16_t seq = 0;
  std::uint32_t last_command_ms = 0;
};

// A command above the regulators' range reaches the firmware (a host without the host-side gate): it is clamped to
// 137 kPa, never passed on.
TEST(FirmwareInTheLoop, CommandAboveTheLimitIsClamped) {
  RawHost h;
  h.send(wire::kHelloPacket, {wire::kProtocolVersion});
  h.rig.run_for_ms(20);
  h.command_for(5000, 600);  // 500 kPa
  EXPECT_GT(h.board.stats().max_setpoint_kpa, 130.0);
  EXPECT_LE(h.board.stats().max_setpoint_kpa, 137.0 + 1e-9);
}

// Garbage on the line in a session: never acted on (no setpoint beyond what was commanded), and a burst long enough
// to keep valid commands from arriving for the watchdog's 40 ms vents within 50 ms of the last valid command.
TEST(FirmwareInTheLoop, GarbageIsNeverActedOnAndAStarvedLinkVents) {
  RawHost h;
  h.send(wire::kHelloPacket, {wire::kProtocolVersion});
  h.rig.run_for_ms(20);
  h.command_for(800, 300);  // 80 kPa
  ASSERT_FALSE(h.board.stats().vented);
  std::mt19937 rng(7);
  std::string junk(2000, '\0');  // 174 ms of line time at 115200 baud
  for (char& c : junk) c = static_cast<char>(rng() & 0xFF);
  const std::uint32_t last_valid = h.last_command_ms;
  h.link->write_all(junk.data(), junk.size());
  h.command_for(800, 300);  // queued behind the garbage
  const long vent = first_vent_from(h.board.stats(), last_valid);
  ASSERT_GE(vent, 0);
  EXPECT_LE(vent - static_cast<long>(last_valid), 50);
  EXPECT_LE(h.board.stats().max_setpoint_kpa, 80.0 + 0.5 * 137.0 / 255.0);
  EXPECT_TRUE(h.board.stats().vented);
}

// Regression (found by this board): an IMU that acknowledges and then never sends the bytes asked for left the bus's
// last byte in every quaternion register; the firmware took that (norm 6.8) as a reading, and the regulators stayed
// pressurised with made-up angles. A reading now needs a unit quaternion (norm within 10 %), and the Wire library gives
// up on a held bus after 5 ms: the gate's IMU timeout vents.
TEST(FirmwareInTheLoop, StuckImuVentsWithin50ms) {
  Session s;
  const long vent_ms = ms_from_imu_fault_to_vent(s, &AvrBoard::set_imu_stuck, 300);
  ASSERT_GE(vent_ms, 0);
  EXPECT_LE(vent_ms, 50);
}

// Regression (found by this board): an IMU that resets (a brown-out) answers again at once, in CONFIG mode, with a
// zero quaternion; the firmware only restarted an IMU after a bus error, so it rejected the zeros and vented for ever.
// Now ten non-unit readings in a row (100 ms) start the IMU again, and the next session runs.
TEST(FirmwareInTheLoop, ImuThatResetsIsStartedAgain) {
  Session s;
  s.command_for(80.0, 300);
  ASSERT_FALSE(s.board.stats().vented);
  const std::uint32_t reset = s.rig.now_ms();
  s.board.reset_imu(1);
  try {
    s.command_for(80.0, 200);
  } catch (const bridge::BridgeFault&) {  // the device's IMU fault flag
  }
  const long vent = s.vent_after(reset);
  ASSERT_GE(vent, 0);
  EXPECT_LE(vent - static_cast<long>(reset), 50);
  s.rig.run_for_ms(300);
  ASSERT_NO_THROW(s.host.start_session());
  s.command_for(30.0, 500);
  EXPECT_NEAR(s.board.setpoints_kpa()[0], 30.0, 1.0);
  EXPECT_EQ(s.board.stats().resets, 0);
}

// A hung program (loop() stops running; the timers keep the regulators' PWM where it was): only the AVR's hardware
// watchdog can vent, by resetting the board, whose pins then float and the regulators' pull-downs vent them. The board
// comes back vented, without a session, answers the next hello and runs again: after a watchdog reset the AVR keeps its
// watchdog on at its shortest period (16 ms; ATmega328P datasheet, 10.9.2, WDRF overrides WDE), which reset the
// firmware again in its 45 ms IMU start-up, for ever, before the firmware cleared it first thing (regression, found by
// this board).
TEST(FirmwareInTheLoop, HungFirmwareIsResetByTheHardwareWatchdogAndComesBackVented) {
  Session s;
  s.command_for(80.0, 300);
  ASSERT_FALSE(s.board.stats().vented);
  ASSERT_EQ(s.board.stats().resets, 0);
  const std::uint32_t hang = s.rig.now_ms();
  s.board.hang_firmware();
  std::string host_told;
  try {
    s.command_for(80.0, 300);
  } catch (const bridge::BridgeFault& e) {
    host_told = e.what();  // the data stopped with the loop: the host vents and stops
  }
  s.rig.run_for_ms(100);
  const long vent = s.vent_after(hang);
  ASSERT_GE(vent, 0);
  EXPECT_LE(vent - static_cast<long>(hang), 50);
  ASSERT_GE(s.board.stats().resets, 1);
  EXPECT_LE(s.board.stats().reset_ms.front() - hang, 50U);
  EXPECT_FALSE(host_told.empty()) << "the host was not told the device lost its session";
  s.rig.run_for_ms(500);
  EXPECT_EQ(s.board.stats().resets, 1) << "the board kept resetting";
  EXPECT_TRUE(s.board.stats().vented);
  ASSERT_NO_THROW(s.host.start_session());
  s.command_for(30.0, 500);
  EXPECT_NEAR(s.board.setpoints_kpa()[0], 30.0, 1.0);
  EXPECT_EQ(s.board.stats().resets, 1);
}

}  // namespace
}  // namespace softwrist::hil
