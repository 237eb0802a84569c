#include "bridge_apps/fault_relay.h"

#include <optional>
#include <stdexcept>

namespace softwrist::bridge {

FaultRelay::FaultRelay(SerialPort device, LineFaultOptions options)
    : device_(std::move(device)), schedule_(options), started_(std::chrono::steady_clock::now()) {
  thread_ = std::thread([this] { run(); });
  // The host may open its side once the relay's first pseudo-terminal exists.
  while (host_path().empty()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

FaultRelay::~FaultRelay() {
  stop_ = true;
  thread_.join();
}

std::string FaultRelay::host_path() const {
  std::lock_guard lock(mutex_);
  return host_path_;
}

std::vector<InjectedFault> FaultRelay::faults() const {
  std::lock_guard lock(mutex_);
  return faults_;
}

void FaultRelay::run() {
  std::optional<PseudoTerminal> host = PseudoTerminal::Open();
  {
    std::lock_guard lock(mutex_);
    host_path_ = host->slave_path;
  }
  char buffer[512];
  while (!stop_) {
    const double now_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    const LineFaults::Change change = schedule_.advance(now_s);
    if (change == LineFaults::Change::kOnset) {
      std::lock_guard lock(mutex_);
      faults_.push_back(*schedule_.active());
      if (schedule_.active()->kind == LinkFault::kLinkCut) {
        host.reset();  // the host's side reads EIO: unplugged
        host_path_.clear();
      }
    } else if (change == LineFaults::Change::kEnd && !host) {
      host = PseudoTerminal::Open();  // plugged in again: a new device node, as a USB serial port gets
      std::lock_guard lock(mutex_);
      host_path_ = host->slave_path;
    }

    // Device to host: waits up to 1 ms, which paces the loop.
    std::size_t n = 0;
    try {
      n = device_.read_some(buffer, sizeof buffer, 1);
    } catch (const std::runtime_error&) {
      return;  // the emulator is gone
    }
    if (n > 0 && schedule_.pass_to_host(buffer, n) && host) {
      try {
        host->master.write_some(buffer, n);  // what does not fit is lost, as on a UART
      } catch (const std::runtime_error&) {  // no host on the other side yet: the bytes are lost
      }
    }

    // Host to device.
    n = 0;
    if (host) {
      try {
        n = host->master.read_some(buffer, sizeof buffer, 0);
      } catch (const std::runtime_error&) {  // the host closed its side (or never opened it)
      }
    }
    if (n > 0 && schedule_.pass_to_device(buffer, n)) {
      try {
        device_.write_some(buffer, n);
      } catch (const std::runtime_error&) {
        return;
      }
    }
  }
}

}  // namespace softwrist::bridge
