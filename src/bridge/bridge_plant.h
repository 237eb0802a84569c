#pragma once
// The Plant (control/plant.h) of the real exosuit: the regulators and the IMU pair behind the firmware (firmware/)
// or the device emulator (device_emulator.h), over a serial link speaking the line protocol (wire_format.h,
// docs/bridge-protocol.md). A controller written against control::Plant runs on it unchanged.
//
// Safety on the host, before anything is sent (the device enforces the same rules again with the same code):
//   - every command passes a wire::SafetyGate with the stricter of the host's and the device's limits;
//   - a command outside the regulator range, or NaN, is a fault (a broken controller), not something to clamp;
//   - a fault vents: the plant sends an emergency stop, ends the session and throws BridgeFault naming the cause.
//     Faults: the link gone; no valid data packet within the timeout (device silent, or the link full of garbage);
//     the device reporting its watchdog, an emergency stop, an IMU fault or a restart; the host's own watchdog
//     (this process stalled past the timeout between two commands).
// Garbled, unknown and out-of-sequence packets from the device are counted and dropped, never acted on.
//
// Time is the host's monotonic clock from construction (or the simulated clock of a lock-step test rig, clock.h);
// an IMU reading is stamped when its packet arrived.

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "bridge/clock.h"
#include "bridge/host_protocol.h"
#include "bridge/link.h"
#include "bridge/safety_gate.h"
#include "bridge/serial_port.h"
#include "bridge/wire_format.h"
#include "control/plant.h"

namespace softwrist::bridge {

class BridgeFault : public control::PlantFault {
 public:
  using control::PlantFault::PlantFault;
};

struct BridgeOptions {
  wire::SafetyLimits limits;         // the host's own; the stricter of these and the device's apply
  double handshake_timeout_s = 3.0;  // an Uno resets when its port opens and takes ~1.6 s to boot
  double hello_interval_s = 0.25;    // hello is repeated until the device answers
};

struct BridgeStats {
  long commands_sent = 0;
  long data_received = 0;        // valid D packets
  long rejected_by_device = 0;   // R packets: commands the device refused
  long garbled_from_device = 0;  // lines failing the checksum, type, field count or number checks
  long out_of_sequence = 0;      // repeated or stale packets from the device
  long overlong_lines = 0;       // dropped whole
  double max_data_gap_s = 0.0;   // longest time between two valid data packets within a session
};

class BridgePlant final : public control::Plant {
 public:
  // Over a serial port, on the host's monotonic clock.
  explicit BridgePlant(SerialPort link, BridgeOptions options = {});
  // Over any link, on `clock` (which must outlive the plant): a lock-step test rig gives its simulated clock.
  BridgePlant(std::unique_ptr<Link> link, const Clock& clock, BridgeOptions options = {});
  ~BridgePlant() override;  // vents (emergency stop); never throws
  BridgePlant(const BridgePlant&) = delete;
  BridgePlant& operator=(const BridgePlant&) = delete;

  // Hello until the device answers with its version and limits, then waits for its first valid IMU data. The
  // device starts the session vented. Throws BridgeFault when it does not answer in time or speaks another version.
  DeviceInfo start_session();
  // Vents: an emergency stop, latched by the device until the next start_session(). Data keeps arriving.
  void end_session();
  bool in_session() const { return session_; }

  void command_pressures_kpa(const control::Pressures& pressures) override;
  control::ImuReading read_angles() override;
  double time_s() const override;
  // Handles the device's packets until `t`; throws BridgeFault on a fault (in a session) or a lost link.
  void wait_until(double t) override;
  double max_pressure_kpa() const override;

  // From the latest valid data packet: the regulators' measured pressures [kPa] and the status (wire::StatusFlag).
  control::Pressures measured_pressures_kpa() const;
  int device_flags() const { return data_.flags; }
  const BridgeStats& stats() const { return stats_; }
  const DeviceInfo& device() const { return protocol_.device(); }
  const std::string& link_name() const { return link_->name(); }
  // The sequence number the next packet to the device will carry (for the latency benchmark).
  uint16_t next_seq() const { return host_seq_; }

 private:
  uint32_t now_ms() const;
  void send(char type, const int32_t* fields, int count);
  // Reads what arrives within `timeout_ms` and handles every complete line.
  void pump(int timeout_ms);
  void handle_line(const char* line, std::size_t length);
  void handle_data(const DeviceData& data);
  void check_data_fresh();
  [[noreturn]] void fault(const std::string& cause);
  // `clock` null: the plant's own steady clock. (A delegating constructor may not name steady_clock_ itself: the
  // object's members may not be referred to before its constructor begins, C++ [class.cdtor]; clang's UBSan vptr
  // check caught it.)
  BridgePlant(std::unique_ptr<Link> link, const Clock* clock, BridgeOptions options);

  std::unique_ptr<Link> link_;
  SteadyClock steady_clock_;  // the clock when none is given
  const Clock& clock_;
  double epoch_s_;
  BridgeOptions options_;
  wire::LineAssembler lines_;
  wire::SafetyGate gate_;
  HostProtocol protocol_;
  BridgeStats stats_;
  bool session_ = false;
  bool link_lost_ = false;
  bool answered_ = false;  // a V packet arrived since the last hello
  uint16_t host_seq_ = 0;
  uint32_t last_command_ms_ = 0;
  // The latest valid data packet.
  bool have_data_ = false;
  uint32_t data_ms_ = 0;  // host time it arrived
  DeviceData data_;
};

}  // namespace softwrist::bridge
