#include "bridge/fault_relay.h"

#include <optional>
#include <stdexcept>

#include "bridge/host_protocol.h"
#include "bridge/wire_format.h"

namespace softwrist::bridge {

const char* link_fault_name(LinkFault fault) {
  switch (fault) {
    case LinkFault::kLinkCut: return "link_cut";
    case LinkFault::kGarbageToHost: return "garbage_to_host";
    case LinkFault::kGarbageToDevice: return "garbage_to_device";
    case LinkFault::kStall: return "stall";
  }
  return "?";
}

FaultRelay::FaultRelay(SerialPort device, FaultRelayOptions options)
    : device_(std::move(device)), options_(options) {
  if (!(options_.mean_interval_s > 0.0) || !(options_.min_duration_s > 0.0) ||
      !(options_.max_duration_s >= options_.min_duration_s)) {
    throw std::invalid_argument("fault relay: the interval and durations must be positive, min <= max");
  }
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
  using Clock = std::chrono::steady_clock;
  std::mt19937_64 rng(options_.seed);
  const auto seconds = [](double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); };
  std::exponential_distribution<double> interval(1.0 / options_.mean_interval_s);
  std::uniform_real_distribution<double> duration(options_.min_duration_s, options_.max_duration_s);
  std::optional<PseudoTerminal> host = PseudoTerminal::Open();
  {
    std::lock_guard lock(mutex_);
    host_path_ = host->slave_path;
  }
  HostProtocol watch;  // the device's data packets as they pass: is it vented?
  wire::LineAssembler device_lines;
  bool device_vented = true;
  Clock::time_point next_onset = Clock::now() + seconds(options_.mean_interval_s);
  std::optional<InjectedFault> active;
  Clock::time_point active_end;
  char buffer[512];
  // Noise on the line: the bytes in transit replaced by random ones.
  const auto garble = [&](std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) buffer[i] = static_cast<char>(rng() & 0xFF);
  };

  while (!stop_) {
    const Clock::time_point now = Clock::now();
    if (!active && now >= next_onset) {
      active = InjectedFault{.kind = static_cast<LinkFault>(rng() % 4), .onset = now, .duration_s = duration(rng),
                             .device_vented_at_onset = device_vented};
      active_end = now + seconds(active->duration_s);
      std::lock_guard lock(mutex_);
      faults_.push_back(*active);
      if (active->kind == LinkFault::kLinkCut) {
        host.reset();  // the host's side reads EIO: unplugged
        host_path_.clear();
      }
    }
    if (active && now >= active_end) {
      if (active->kind == LinkFault::kLinkCut) {
        host = PseudoTerminal::Open();  // plugged in again: a new device node, as a USB serial port gets
        std::lock_guard lock(mutex_);
        host_path_ = host->slave_path;
      }
      active.reset();
      next_onset = now + seconds(interval(rng));
    }
    const bool blocked = active && (active->kind == LinkFault::kStall || active->kind == LinkFault::kLinkCut);

    // Device to host: waits up to 1 ms, which paces the loop.
    std::size_t n = 0;
    try {
      n = device_.read_some(buffer, sizeof buffer, 1);
    } catch (const std::runtime_error&) {
      return;  // the emulator is gone
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (device_lines.push(buffer[i]) && watch.handle_line(device_lines.line(), device_lines.length()) == DeviceLine::kData) {
        device_vented = (watch.data().flags & wire::kVented) != 0;
      }
    }
    if (active && active->kind == LinkFault::kGarbageToHost) garble(n);
    if (n > 0 && host && !blocked) {
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
    if (active && active->kind == LinkFault::kGarbageToDevice) garble(n);
    if (n > 0 && !blocked) {
      try {
        device_.write_some(buffer, n);
      } catch (const std::runtime_error&) {
        return;
      }
    }
  }
}

}  // namespace softwrist::bridge
