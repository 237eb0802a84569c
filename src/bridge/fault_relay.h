#pragma once
// A serial link that breaks: a relay between the device (the emulator's pseudo-terminal) and the host (a
// pseudo-terminal of its own, whose path the host opens), forwarding bytes both ways in real time and injecting
// faults at random moments, as a long trial meets them (`softwrist soak`, docs/emulator.md):
//   link_cut          the host's side closes (a USB cable pulled); a new one appears after the fault's duration
//   garbage_to_host   what the device sends is replaced by random bytes (electrical noise on the line)
//   garbage_to_device what the host sends is replaced by random bytes
//   stall             nothing passes either way (a USB hub that stalls)
// Every fault lasts longer than the protocol's 40 ms timeout, so each one must end with the device vented. The
// relay watches the device's data packets going through, and so knows whether the device was vented when a fault
// began.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bridge/serial_port.h"

namespace softwrist::bridge {

enum class LinkFault { kLinkCut, kGarbageToHost, kGarbageToDevice, kStall };
const char* link_fault_name(LinkFault fault);

struct InjectedFault {
  LinkFault kind = LinkFault::kStall;
  std::chrono::steady_clock::time_point onset;
  double duration_s = 0.0;
  bool device_vented_at_onset = false;  // per the device's last data packet before the onset
};

struct FaultRelayOptions {
  double mean_interval_s = 20.0;               // between fault onsets (exponential), after a first quiet interval
  double min_duration_s = 0.06, max_duration_s = 0.5;
  std::uint64_t seed = 1;
};

class FaultRelay {
 public:
  // Relays between `device` (opened on the device's side) and a new host-side pseudo-terminal.
  FaultRelay(SerialPort device, FaultRelayOptions options);
  ~FaultRelay();  // stops the thread
  FaultRelay(const FaultRelay&) = delete;
  FaultRelay& operator=(const FaultRelay&) = delete;

  // The path the host opens now: a new one after each link cut; empty while the cable is out.
  std::string host_path() const;
  std::vector<InjectedFault> faults() const;

 private:
  void run();

  SerialPort device_;
  FaultRelayOptions options_;
  mutable std::mutex mutex_;
  std::string host_path_;
  std::vector<InjectedFault> faults_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace softwrist::bridge
