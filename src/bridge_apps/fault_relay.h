#pragma once
// A serial link that breaks, in real time: a relay between the device (the emulator's pseudo-terminal) and the host
// (a pseudo-terminal of its own, whose path the host opens), forwarding bytes both ways and injecting the faults of
// a LineFaults schedule (line_faults.h) on the host's monotonic clock (`softwrist soak`, docs/emulator.md). A link
// cut closes the host's pseudo-terminal; a new one, at a new path, appears when the fault ends.

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bridge/serial_port.h"
#include "bridge_apps/line_faults.h"

namespace softwrist::bridge {

class FaultRelay {
 public:
  // Relays between `device` (opened on the device's side) and a new host-side pseudo-terminal. Throws
  // std::invalid_argument for options LineFaults refuses.
  FaultRelay(SerialPort device, LineFaultOptions options);
  ~FaultRelay();  // stops the thread
  FaultRelay(const FaultRelay&) = delete;
  FaultRelay& operator=(const FaultRelay&) = delete;

  // The path the host opens now: a new one after each link cut; empty while the cable is out.
  std::string host_path() const;
  // The faults so far; their onsets in seconds after started().
  std::vector<InjectedFault> faults() const;
  std::chrono::steady_clock::time_point started() const { return started_; }

 private:
  void run();

  SerialPort device_;
  LineFaults schedule_;
  std::chrono::steady_clock::time_point started_;
  mutable std::mutex mutex_;
  std::string host_path_;
  std::vector<InjectedFault> faults_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace softwrist::bridge
