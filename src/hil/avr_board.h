#pragma once
// Firmware in the loop (issue 21): the real firmware (firmware/softwrist_fw, as scripts/build_firmware.sh builds it)
// on a simulated ATmega328P at 16 MHz (Debian's simavr), wired to the simulated exosuit as firmware/README.md wires
// the Uno, and stepped one millisecond at a time in lock-step with it, so a run is deterministic and can be faster
// than real time. It is a bridge::LineDevice: the lock-step rig (bridge_apps/lockstep_link.h) puts it at the end of
// the host's serial line, and BridgePlant, run_trial and everything above them run unchanged.
//
// The wiring, as the firmware expects it:
//   UART 0 (115200 baud)  <-> the host's line (the rig paces bytes at the line's rate)
//   I2C 0x28, 0x29        <-  two BNO055 slaves answering CHIP_ID (0xA0), OPR_MODE and the fused quaternion
//                             (0x20-0x27, 2^14 LSB per unit), the forearm's fixed and the hand's from the simulated
//                             wrist's IMU angles (noise and posture as the emulator config says)
//   A0-A3                 <-  the regulators' pressure monitors, 0-5 V for 0-137 kPa
//   PWM 3, 5, 6, 9        ->  through an RC low-pass (the emulator config's effects.pwm_filter_time_constant_s, as
//                             the emulator's own) into the regulators' setpoints
//                             (flexor, extensor, ulnar, radial); a pin that is not an output (after a reset) reads 0,
//                             as the regulators' inputs are pulled down
//   pin 7                 ->  the supply valve: closed, every regulator vents
//   pin 8                 <-  the safety switch, closed to ground (a test can open it)
// What it does not model: electrical noise, the QB3's own response beyond the plant's regulator model, the BNO055's
// fusion (it reports the simulated angles exactly, plus the IMU model's noise), the emulator's dead time, IMU
// latency and bias, and the emulator's injected faults (the board has its own: the switch, a silent or stuck I2C
// slave, a hung program).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "bridge_apps/device_emulator.h"
#include "control/plant.h"

namespace softwrist::hil {

inline constexpr std::uint32_t kAvrClockHz = 16'000'000;  // the Uno's crystal
inline constexpr double avr_seconds(std::uint64_t cycles) { return static_cast<double>(cycles) / kAvrClockHz; }
inline constexpr double avr_microseconds(double cycles) { return cycles * 1e6 / kAvrClockHz; }

struct BoardStats {
  std::uint64_t cycles = 0;             // AVR cycles run
  long resets = 0;                      // the AVR restarted (its hardware watchdog), after the power-on one
  std::vector<std::uint32_t> reset_ms;  // when, in AVR milliseconds
  long bytes_from_avr = 0, bytes_to_avr = 0, bytes_lost_to_avr = 0;
  long i2c_reads = 0;             // quaternion reads answered
  double max_setpoint_kpa = 0.0;  // the highest any regulator was told
  // The firmware's timing and memory, in AVR cycles (16 per microsecond) and bytes: each pass of loop() (from one
  // entry to the next), each quaternion read on the bus (START to STOP), and the lowest the stack pointer went above
  // the end of static RAM (__heap_start; the firmware has no heap).
  std::uint64_t loop_max_cycles = 0, loop_cycles_total = 0;
  long loops = 0;
  std::uint64_t i2c_read_max_cycles = 0, i2c_read_cycles_total = 0;
  long i2c_read_transactions = 0;
  int stack_headroom_bytes = 0;
  bool vented = true;                  // every regulator's setpoint 0 now
  std::vector<std::uint32_t> vent_ms;  // each moment the board went from some pressure to vented
};

// The firmware's size from its ELF sections: flash = .text + .data (the initial values are stored in flash), static
// RAM = .data + .bss. Throws std::runtime_error naming the file when it cannot be read.
struct FirmwareSize {
  long flash_bytes = 0, ram_bytes = 0;
};
FirmwareSize firmware_size(const std::filesystem::path& firmware);

class AvrBoard final : public bridge::LineDevice {
 public:
  // Loads `firmware` (an ELF for the ATmega328P) and builds the plant from `plant` (the emulator's config). Throws
  // std::runtime_error naming the file when it cannot be read as AVR firmware.
  AvrBoard(const std::filesystem::path& firmware, const bridge::EmulatorConfig& plant);
  ~AvrBoard() override;
  AvrBoard(const AvrBoard&) = delete;
  AvrBoard& operator=(const AvrBoard&) = delete;

  void receive(const char* data, std::size_t size) override;
  void tick(std::uint32_t t_ms, bridge::DeviceUart& uart) override;

  // Faults a test causes: the safety switch opened (or closed again); an IMU (0 forearm, 1 hand) that stops
  // answering on the bus (or answers again).
  void set_safety_switch_open(bool open);
  void set_imu_silent(int imu, bool silent);
  // An IMU that acknowledges its address, then never sends the bytes asked for.
  void set_imu_stuck(int imu, bool stuck);
  // An IMU that resets (a brown-out): it answers again at once, in CONFIG mode, with a zero quaternion until the
  // firmware selects a fusion mode again.
  void reset_imu(int imu);
  // The program hangs (a corrupted pointer, an interrupt that never returns, a library waiting forever): from now
  // until the AVR next resets, loop() spins at its entry (its first instruction becomes a jump to itself), while
  // the timers, their PWM and the interrupts run on. Only the AVR's hardware watchdog gets the board out of it; the
  // reset clears the fault, as a power cycle clears a transient one.
  void hang_firmware();

  const BoardStats& stats() const;
  control::Pressures setpoints_kpa() const;  // what the regulators are told now (after the filter and the valve)
  control::WristAngles true_angles() const;  // the simulated wrist's joint angles [deg]
  control::Pressures regulated_pressures_kpa() const;  // what the simulated regulators hold now

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace softwrist::hil
