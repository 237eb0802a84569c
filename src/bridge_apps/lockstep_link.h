#pragma once
// The host and the emulated device on one simulated clock (issue 27): a test rig in which the bridge's timing
// rules are checked exactly, the same on every machine, in every build and however busy the host is.
//
// The rig owns the time. It advances in steps of one millisecond, and in each the line carries bytes both ways at
// the UART's rate (115200 baud, 8N1: 11.52 bytes per ms), the faults of an optional LineFaults schedule act on
// them, and the device (DeviceEmulator) runs one pass of its firmware loop. The host side is a Link (link.h) whose
// reads advance the rig while they wait, and the rig is the host's Clock (clock.h): a BridgePlant built on both
// runs a whole trial in simulated time, as fast as the machine allows. The host's own computing takes no simulated
// time; a host that stalls is a test calling run_for_ms while holding its plant.
//
// One thread: the rig, its links and the plant on it are not to be shared between threads.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "bridge/clock.h"
#include "bridge/link.h"
#include "bridge_apps/device_emulator.h"
#include "bridge_apps/line_faults.h"

namespace softwrist::bridge {

struct LockstepOptions {
  int baud = 115200;                       // the Uno's serial line (firmware/README.md)
  std::size_t buffer_bytes = 4096;         // each side's receive buffer; what does not fit is lost
  std::optional<LineFaultOptions> faults;  // faults on the line, as the soak's relay injects them
};

class LockstepLink final : public Clock {
 public:
  // The device's first loop pass runs at 0 ms. Throws std::invalid_argument for a baud rate <= 0.
  explicit LockstepLink(LineDevice& device, LockstepOptions options = {});
  ~LockstepLink() override;
  LockstepLink(const LockstepLink&) = delete;
  LockstepLink& operator=(const LockstepLink&) = delete;

  double now_s() const override { return now_ms_ / 1000.0; }
  std::uint32_t now_ms() const { return now_ms_; }

  // The host's end of the cable, as SerialPort::Open gives it. Reads from it advance the rig; it reads "gone"
  // once the cable is pulled (a link-cut fault), as a USB serial port does, and a new end must be opened after the
  // cable is back. Throws std::runtime_error while the cable is out.
  std::unique_ptr<Link> open_host();
  bool cable_in() const { return cable_in_ && !device_cut_; }

  // Lets the device run alone (the host stalled, or a test waiting for the device).
  void run_for_ms(std::uint32_t ms);
  // Faults injected on the line so far (onsets in seconds of this clock).
  const std::vector<InjectedFault>& faults() const;
  // Called after each millisecond with the time [ms].
  void set_tick_observer(std::function<void(std::uint32_t)> observer) { observer_ = std::move(observer); }

 private:
  class HostEnd;
  class Uart;
  friend class HostEnd;
  void tick();
  void carry(std::deque<char>& wire, double& credit, bool to_host);
  void drop_host();

  LineDevice& device_;
  LockstepOptions options_;
  std::unique_ptr<Uart> uart_;
  std::optional<LineFaults> faults_;
  std::function<void(std::uint32_t)> observer_;
  std::uint32_t now_ms_ = 0;
  double bytes_per_ms_;
  std::deque<char> to_host_, to_device_;  // on the wire
  double credit_to_host_ = 0.0, credit_to_device_ = 0.0;
  std::deque<char> host_received_;  // arrived at the host, not yet read
  bool cable_in_ = true;            // false during a link-cut fault on the line
  bool device_cut_ = false;         // the device's own link-cut fault: for good
  bool host_open_ = false;
  int generation_ = 0;  // of the host's end: a cut ends it
};

}  // namespace softwrist::bridge
