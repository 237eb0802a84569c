#pragma once
// The device emulator: what the firmware does (firmware/softwrist_fw), on the device side of a serial link, with a
// simulated exosuit in place of the regulators and IMUs. It is how the bridge is tested here and how a user
// rehearses a hardware trial (`softwrist emulate`). It runs on its own millisecond clock, driven either in real
// time over a pseudo-terminal (serve) or in simulated time by a lock-step rig (lockstep_link.h), where every
// timing property of the safety rules is exact and the same on every machine.
//
// The exosuit is the simulation (MuJoCo with the fPAM plugin, sim::SimulatedPlant) of a placement file, with extra
// effects a real device has and the nominal model lacks, each off unless its config names it (docs/emulator.md):
//   mount_stretch  mounting-point stiffness K1, K2 other than the placement file's (self-consistent stretching);
//   regulator_lag  another regulator time constant, and a dead time before a setpoint reaches the regulator;
//   imu            white noise, a fixed bias and a latency of the measured wrist angles.
// At each hello the emulated subject puts the wrist at neutral and holds it still, vented, until the first command
// (the paper zeroes the angles at the neutral wrist), then lets go.
// Faults can be scheduled (seconds after the first hello): the IMUs going stale, a burst of garbage towards the
// host, the link cut. The device side runs the same wire::SafetyGate as the firmware, updated every millisecond,
// and records every moment it vents with the cause, so tests can check how quickly a fault made it safe.

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "bridge/safety_gate.h"
#include "bridge/serial_port.h"
#include "bridge/wire_format.h"
#include "physics/mount_stretch.h"
#include "sim/device.h"

namespace softwrist::bridge {

inline constexpr const char* kEmulatorFormat = "softwrist.emulator/1";

struct EmulatorEffects {
  std::optional<physics::MountStiffness> mount_stiffness;  // [N/m^2]; replaces the placement file's
  std::optional<double> regulator_time_constant_s;         // replaces the placement file's
  double wrist_stiffness_scale = 1.0;                      // the relaxed wrist's stiffness, both axes, times this
  double wrist_damping_scale = 1.0;                        // and its damping
  // The regulators see the setpoints through the firmware's 8-bit PWM (bridge/pwm_scaling.h), as on the Uno; off,
  // exactly (to compare the bridge's path with the simulation, which has no PWM).
  bool pwm_steps = true;
  // The RC low-pass between each PWM pin and its regulator's 0-10 V input (with pwm_steps; the firmware in the loop's
  // board has the same): 10 ms, assumed; firmware/README.md asks for a filter well above the PWM's 1-2 ms period and
  // well below the regulator's own 0.1 s. 0: none.
  double pwm_filter_time_constant_s = 0.010;
  double regulator_dead_time_s = 0.0;
  double imu_noise_std_deg = 0.0;
  double imu_bias_fe_deg = 0.0, imu_bias_ur_deg = 0.0;
  double imu_latency_s = 0.0;
};

struct EmulatorFaults {          // seconds after the first hello; negative: never
  double imu_stale_at_s = -1.0;  // the IMUs stop giving valid readings (a BNO055 that stops answering on I2C)
  double garbage_at_s = -1.0;    // random bytes towards the host
  int garbage_bytes = 300;
  double link_cut_at_s = -1.0;  // the link closes (a USB cable pulled); the device keeps running
};

struct EmulatorConfig {
  std::filesystem::path model;  // placement file of the "real" device
  double gravity = 9.81;        // [m/s^2]; 0 with the hand supported on a table
  EmulatorEffects effects;
  EmulatorFaults faults;
  wire::SafetyLimits limits;
  std::uint64_t seed = 1;
};

// The board's RC filter between a PWM pin and its regulator over a step of dt_s: the share of the way from its output
// to its input it moves (first order, exact for an input held over the step; 1 without a filter). One law for the
// emulator and the firmware in the loop's board.
inline double pwm_filter_blend(double dt_s, double time_constant_s) {
  return time_constant_s > 0.0 ? 1.0 - std::exp(-dt_s / time_constant_s) : 1.0;
}

// Reads an emulator config (format softwrist.emulator/1); relative paths start at the file's directory. Errors
// throw std::runtime_error("<file>: <field>: <problem>").
EmulatorConfig load_emulator_config(const std::filesystem::path& path);

// The emulated device's own description: the placement file with the effects that live in it applied (mounts,
// regulator time constant, relaxed wrist). What a model of the emulated device would be if it were exact, less the
// dead time and the IMU effects, which act outside the placement (the calibration benchmark's "true model").
sim::DeviceDescription emulated_description(const EmulatorConfig& config);

// A moment the device vented (all regulator setpoints to 0, supply valve closed).
struct VentEvent {
  std::uint32_t t_ms = 0;      // device clock: ms since the device started
  std::string cause;           // "emergency stop", "zero command", "watchdog: no command", "watchdog: no IMU"
  std::uint32_t cause_ms = 0;  // when the cause began: the packet's arrival, or the last valid command or IMU
                               // reading before the timeout
};

struct EmulatorStats {
  long packets_accepted = 0;
  long packets_rejected = 0;  // each answered with an R packet
  long data_sent = 0;
  long bytes_dropped = 0;  // did not fit the link's buffer (no host reading)
  long sessions = 0;
  int32_t max_output_dkpa = 0;                     // the highest setpoint the regulators were ever given
  std::uint32_t max_loop_lag_ms = 0;               // how far serve()'s loop fell behind real time (a loaded machine)
  std::uint32_t fault_injected_ms[3] = {0, 0, 0};  // imu stale, garbage, link cut; 0: not injected
  std::vector<VentEvent> vents;
  bool vented = true;                           // now: every regulator setpoint 0
  std::chrono::steady_clock::time_point epoch;  // serve()'s start: the device clock's zero (real time only)
  std::string stopped_by;  // why serve() stopped before it was asked to (the simulation failed); empty otherwise
};

// The device's end of the link as the emulated firmware sees it: a UART that drops what does not fit, and a cable
// that a fault can pull.
class DeviceUart {
 public:
  virtual ~DeviceUart() = default;
  // Sends what fits; returns how many bytes were dropped.
  virtual std::size_t write(const char* data, std::size_t size) = 0;
  // The link-cut fault: the host's side reads "gone" from now on (the device keeps running).
  virtual void cut() = 0;
};

// A device at the end of a serial line, stepped one millisecond at a time by whoever owns the time (the lock-step
// rig, lockstep_link.h): the emulator below, or the real firmware on a simulated board (src/hil/avr_board.h).
class LineDevice {
 public:
  virtual ~LineDevice() = default;
  // Bytes from the host, as they arrive on the line.
  virtual void receive(const char* data, std::size_t size) = 0;
  // The device's millisecond ending at `t_ms` (one more than the last tick's; the first tick is at 0).
  virtual void tick(std::uint32_t t_ms, DeviceUart& uart) = 0;
};

class DeviceEmulator final : public LineDevice {
 public:
  explicit DeviceEmulator(const EmulatorConfig& config);
  ~DeviceEmulator();
  DeviceEmulator(const DeviceEmulator&) = delete;
  DeviceEmulator& operator=(const DeviceEmulator&) = delete;

  // The device in steps of its own clock, driven by whoever owns the time (a lock-step rig, lockstep_link.h, or
  // serve() below). Device time starts at 0 ms and is advanced one millisecond at a time.
  //   receive: bytes from the host, acted on at the next tick, as the firmware reads its serial buffer in its loop;
  //   tick:    one pass of the firmware's loop at device time `t_ms` (one more than the last tick's).
  // tick() throws std::runtime_error when the simulated exosuit fails (an unstable simulation).
  void receive(const char* data, std::size_t size) override;
  void tick(std::uint32_t t_ms, DeviceUart& uart) override;

  // Serves a serial port (the emulator's pseudo-terminal) in real time until `stop` is set: ticks at the rate of
  // the host's monotonic clock, catching up when it fell behind. The link may go (cut, or the host gone): the
  // device keeps running (its watchdog vents) and, for a host that went, listens for the next one. Should the
  // simulated exosuit fail, it stops, closing the link (the host sees it lost and vents), with the reason in
  // stats().stopped_by.
  void serve(SerialPort link, const std::atomic<bool>& stop);
  // A copy, safe to take while serve() runs.
  EmulatorStats stats() const;
  // serve() stopped on its own (stats().stopped_by says why).
  bool failed() const { return failed_.load(); }
  // Called as each packet from the host is accepted (for the latency benchmark). Set before the device runs.
  void set_packet_observer(std::function<void(char type, std::uint16_t seq)> observer) {
    observer_ = std::move(observer);
  }

 private:
  struct Device;
  struct Firmware;
  void serve_device(SerialPort link, const std::atomic<bool>& stop);
  void handle_line(std::uint32_t now, DeviceUart& uart);
  void inject_faults(std::uint32_t t, DeviceUart& uart);
  void sample_imus(std::uint32_t t, DeviceUart& uart);
  void update_outputs(std::uint32_t t);
  void write(const char* data, std::size_t size, DeviceUart& uart);  // counts what the UART dropped
  void send(const wire::Packet& packet, DeviceUart& uart);

  EmulatorConfig config_;
  std::unique_ptr<Device> device_;
  std::unique_ptr<Firmware> firmware_;
  mutable std::mutex mutex_;
  EmulatorStats stats_;
  std::function<void(char, std::uint16_t)> observer_;
  std::atomic<bool> failed_{false};
};

}  // namespace softwrist::bridge
