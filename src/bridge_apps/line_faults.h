#pragma once
// Faults on the serial line, as a long trial meets them (`softwrist soak`, docs/emulator.md), on a schedule of
// random onsets (exponential intervals) and durations:
//   link_cut          the host's side closes (a USB cable pulled); a new one appears after the fault's duration
//   garbage_to_host   what the device sends is replaced by random bytes (electrical noise on the line)
//   garbage_to_device what the host sends is replaced by random bytes
//   stall             nothing passes either way (a USB hub that stalls)
// Every fault lasts longer than the protocol's 40 ms timeout, so each one must end with the device vented. The
// schedule watches the device's data packets going through, and so knows whether the device was vented when a
// fault began. One schedule, on whichever clock carries the line: the real-time relay between pseudo-terminals
// (fault_relay.h) and the lock-step rig in simulated time (lockstep_link.h).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "bridge/host_protocol.h"
#include "bridge/wire_format.h"

namespace softwrist::bridge {

enum class LinkFault { kLinkCut, kGarbageToHost, kGarbageToDevice, kStall };
const char* link_fault_name(LinkFault fault);

struct InjectedFault {
  LinkFault kind = LinkFault::kStall;
  double onset_s = 0.0;  // on the schedule's clock
  double duration_s = 0.0;
  bool device_vented_at_onset = false;  // per the device's last data packet before the onset
};

struct LineFaultOptions {
  double mean_interval_s = 20.0;  // between fault onsets (exponential), after a first quiet interval
  double min_duration_s = 0.06, max_duration_s = 0.5;
  std::uint64_t seed = 1;
};

class LineFaults {
 public:
  // Throws std::invalid_argument for an interval or durations that are not positive, or min > max.
  explicit LineFaults(LineFaultOptions options);

  enum class Change { kNone, kOnset, kEnd };
  // Advances the schedule to `now_s` (seconds on the line's clock, from 0): a fault may begin or end.
  Change advance(double now_s);
  const std::optional<InjectedFault>& active() const { return active_; }
  const std::vector<InjectedFault>& faults() const { return faults_; }

  // Bytes in transit, one direction each: true when they pass (garbled in place while noise is on that
  // direction), false when they are lost (a stall, the cable out).
  bool pass_to_host(char* data, std::size_t size);
  bool pass_to_device(char* data, std::size_t size);

 private:
  bool blocked() const;
  void garble(char* data, std::size_t size);

  LineFaultOptions options_;
  std::mt19937_64 rng_;
  std::exponential_distribution<double> interval_;
  std::uniform_real_distribution<double> duration_;
  double next_onset_s_;
  std::optional<InjectedFault> active_;
  std::vector<InjectedFault> faults_;
  HostProtocol watch_;  // the device's data packets as they pass: is it vented?
  wire::LineAssembler device_lines_;
  bool device_vented_ = true;
};

}  // namespace softwrist::bridge
