#pragma once
// The device emulator: what the firmware does (firmware/softwrist_fw), in real time, on the device side of a
// serial link (a pseudo-terminal), with a simulated exosuit in place of the regulators and IMUs. It is how the
// bridge is tested here and how a user rehearses a hardware trial (`softwrist emulate`).
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
#include "physics/mount_stretch.h"

namespace softwrist::bridge {

inline constexpr const char* kEmulatorFormat = "softwrist.emulator/1";

struct EmulatorEffects {
  std::optional<physics::MountStiffness> mount_stiffness;  // [N/m^2]; replaces the placement file's
  std::optional<double> regulator_time_constant_s;          // replaces the placement file's
  double regulator_dead_time_s = 0.0;
  double imu_noise_std_deg = 0.0;
  double imu_bias_fe_deg = 0.0, imu_bias_ur_deg = 0.0;
  double imu_latency_s = 0.0;
};

struct EmulatorFaults {  // seconds after the first hello; negative: never
  double imu_stale_at_s = -1.0;  // the IMUs stop giving valid readings (a BNO055 that stops answering on I2C)
  double garbage_at_s = -1.0;    // random bytes towards the host
  int garbage_bytes = 300;
  double link_cut_at_s = -1.0;   // the link closes (a USB cable pulled); the device keeps running
};

struct EmulatorConfig {
  std::filesystem::path model;  // placement file of the "real" device
  double gravity = 9.81;        // [m/s^2]; 0 with the hand supported on a table
  EmulatorEffects effects;
  EmulatorFaults faults;
  wire::SafetyLimits limits;
  std::uint64_t seed = 1;
};

// Reads an emulator config (format softwrist.emulator/1); relative paths start at the file's directory. Errors
// throw std::runtime_error("<file>: <field>: <problem>").
EmulatorConfig load_emulator_config(const std::filesystem::path& path);

// A moment the device vented (all regulator setpoints to 0, supply valve closed).
struct VentEvent {
  std::uint32_t t_ms = 0;          // device clock: ms since serve() began
  std::string cause;               // "emergency stop", "zero command", "watchdog: no command", "watchdog: no IMU"
  std::uint32_t cause_ms = 0;      // when the cause began: the packet's arrival, or the last valid command or IMU
                                   // reading before the timeout
};

struct EmulatorStats {
  long packets_accepted = 0;
  long packets_rejected = 0;  // each answered with an R packet
  long data_sent = 0;
  long bytes_dropped = 0;     // did not fit the link's buffer (no host reading)
  long sessions = 0;
  int32_t max_output_dkpa = 0;        // the highest setpoint the regulators were ever given
  std::uint32_t max_loop_lag_ms = 0;  // how far the emulated loop fell behind real time (a loaded machine)
  std::uint32_t fault_injected_ms[3] = {0, 0, 0};  // imu stale, garbage, link cut; 0: not injected
  std::vector<VentEvent> vents;
  std::chrono::steady_clock::time_point epoch;  // serve()'s start: the device clock's zero
  std::string stopped_by;  // why serve() stopped before it was asked to (the simulation failed); empty otherwise
};

class DeviceEmulator {
 public:
  explicit DeviceEmulator(const EmulatorConfig& config);
  ~DeviceEmulator();
  DeviceEmulator(const DeviceEmulator&) = delete;
  DeviceEmulator& operator=(const DeviceEmulator&) = delete;

  // Serves `link` in real time until `stop` is set. The link may go (cut, or the host gone): the device keeps
  // running (its watchdog vents) and, for a host that went, listens for the next one. Should the simulated exosuit
  // fail (an unstable simulation), it stops, closing the link (the host sees it lost and vents), with the reason
  // in stats().stopped_by.
  void serve(SerialPort link, const std::atomic<bool>& stop);
  // A copy, safe to take while serve() runs.
  EmulatorStats stats() const;
  // serve() stopped on its own (stats().stopped_by says why).
  bool failed() const { return failed_.load(); }
  // Called from serve()'s thread as each packet from the host is accepted (for the latency benchmark). Set before
  // serve() starts.
  void set_packet_observer(std::function<void(char type, std::uint16_t seq)> observer) { observer_ = std::move(observer); }

 private:
  struct Device;
  void serve_device(SerialPort link, const std::atomic<bool>& stop);
  EmulatorConfig config_;
  std::unique_ptr<Device> device_;
  mutable std::mutex mutex_;
  EmulatorStats stats_;
  std::function<void(char, std::uint16_t)> observer_;
  std::atomic<bool> failed_{false};
};

}  // namespace softwrist::bridge
