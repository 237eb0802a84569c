#include "bridge_apps/lockstep_link.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace softwrist::bridge {

// The device's UART on the rig's line.
class LockstepLink::Uart final : public DeviceUart {
 public:
  explicit Uart(LockstepLink& rig) : rig_(rig) {}
  std::size_t write(const char* data, std::size_t size) override {
    const std::size_t room = rig_.options_.buffer_bytes - std::min(rig_.options_.buffer_bytes, rig_.to_host_.size());
    const std::size_t n = std::min(room, size);
    rig_.to_host_.insert(rig_.to_host_.end(), data, data + n);
    return size - n;
  }
  void cut() override {
    rig_.device_cut_ = true;
    rig_.drop_host();
  }

 private:
  LockstepLink& rig_;
};

// The host's end of the cable.
class LockstepLink::HostEnd final : public Link {
 public:
  HostEnd(LockstepLink& rig, int generation)
      : rig_(rig), generation_(generation), name_(fmt::format("lockstep-link#{}", generation)) {}
  ~HostEnd() override {
    if (alive()) rig_.host_open_ = false;
  }

  void write_all(const char* data, std::size_t size) override { write_some(data, size); }
  std::size_t write_some(const char* data, std::size_t size) override {
    if (!alive()) throw std::runtime_error(name_ + ": write failed (the link is gone)");
    rig_.to_device_.insert(rig_.to_device_.end(), data, data + size);
    return size;
  }
  std::size_t read_some(char* buffer, std::size_t size, int timeout_ms) override {
    for (int waited = 0; alive() && rig_.host_received_.empty() && waited < timeout_ms; ++waited) rig_.tick();
    if (!alive()) throw std::runtime_error(name_ + ": the link is gone");
    const std::size_t n = std::min(size, rig_.host_received_.size());
    std::copy_n(rig_.host_received_.begin(), n, buffer);
    rig_.host_received_.erase(rig_.host_received_.begin(), rig_.host_received_.begin() + static_cast<long>(n));
    return n;
  }
  const std::string& name() const override { return name_; }

 private:
  bool alive() const { return rig_.generation_ == generation_ && rig_.cable_in(); }

  LockstepLink& rig_;
  int generation_;
  std::string name_;
};

LockstepLink::LockstepLink(LineDevice& device, LockstepOptions options)
    : device_(device), options_(std::move(options)), uart_(std::make_unique<Uart>(*this)) {
  if (options_.baud <= 0) throw std::invalid_argument("lockstep link: the baud rate must be > 0");
  bytes_per_ms_ = options_.baud / 10.0 / 1000.0;  // 8N1: ten bits a byte
  if (options_.faults) faults_.emplace(*options_.faults);
  device_.tick(0, *uart_);
}

LockstepLink::~LockstepLink() = default;

std::unique_ptr<Link> LockstepLink::open_host() {
  if (!cable_in()) throw std::runtime_error("lockstep link: the cable is out");
  if (host_open_) throw std::logic_error("lockstep link: the host's end is open already");
  host_open_ = true;
  host_received_.clear();
  return std::make_unique<HostEnd>(*this, generation_);
}

void LockstepLink::run_for_ms(std::uint32_t ms) {
  for (std::uint32_t k = 0; k < ms; ++k) tick();
}

const std::vector<InjectedFault>& LockstepLink::faults() const {
  static const std::vector<InjectedFault> kNone;
  return faults_ ? faults_->faults() : kNone;
}

void LockstepLink::drop_host() {
  cable_in_ = false;
  host_open_ = false;
  ++generation_;
}

// Moves what the line carries in one millisecond from `wire` to its receiver.
void LockstepLink::carry(std::deque<char>& wire, double& credit, bool to_host) {
  credit = std::min(credit + bytes_per_ms_, bytes_per_ms_ + 1.0);  // an idle line saves up no more than a byte
  const std::size_t n = std::min(wire.size(), static_cast<std::size_t>(credit));
  credit -= static_cast<double>(n);
  if (n == 0) return;
  std::string bytes(wire.begin(), wire.begin() + static_cast<long>(n));
  wire.erase(wire.begin(), wire.begin() + static_cast<long>(n));
  if (to_host) {
    const bool passes = !faults_ || faults_->pass_to_host(bytes.data(), bytes.size());
    if (!passes || !cable_in() || !host_open_) return;
    const std::size_t room = options_.buffer_bytes - std::min(options_.buffer_bytes, host_received_.size());
    host_received_.insert(host_received_.end(), bytes.begin(), bytes.begin() + static_cast<long>(std::min(room, n)));
  } else {
    const bool passes = !faults_ || faults_->pass_to_device(bytes.data(), bytes.size());
    if (passes && cable_in()) device_.receive(bytes.data(), bytes.size());
  }
}

void LockstepLink::tick() {
  ++now_ms_;
  if (faults_) {
    const LineFaults::Change change = faults_->advance(now_s());
    if (change == LineFaults::Change::kOnset && faults_->active()->kind == LinkFault::kLinkCut) {
      drop_host();
      to_device_.clear();  // what the host had sent is in the cable that went
    } else if (change == LineFaults::Change::kEnd && !cable_in_) {
      cable_in_ = true;  // plugged in again: the host opens the new device node
    }
  }
  carry(to_device_, credit_to_device_, false);
  carry(to_host_, credit_to_host_, true);
  device_.tick(now_ms_, *uart_);
  if (observer_) observer_(now_ms_);
}

}  // namespace softwrist::bridge
