#include "bridge/bridge_plant.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "physics/exosuit_layout.h"

namespace softwrist::bridge {
namespace {

// safety_gate.h is freestanding (the firmware compiles it), so it states the regulators' range in its own units.
static_assert(wire::SafetyLimits().max_dkpa == static_cast<int32_t>(physics::kRegulatorMaxPressureKpa * 10.0),
              "the device's pressure limit is the regulators' range");

// The stricter of two sets of limits.
wire::SafetyLimits stricter(const wire::SafetyLimits& a, const wire::SafetyLimits& b) {
  wire::SafetyLimits s;
  s.max_dkpa = std::min(a.max_dkpa, b.max_dkpa);
  s.rate_dkpa_s = std::min(a.rate_dkpa_s, b.rate_dkpa_s);
  s.timeout_ms = std::min(a.timeout_ms, b.timeout_ms);
  return s;
}

std::string describe_flags(int flags) {
  std::string out;
  const auto add = [&](int flag, const char* name) {
    if (!(flags & flag)) return;
    if (!out.empty()) out += ", ";
    out += name;
  };
  add(wire::kWatchdog, "its watchdog vented (no valid command or IMU reading within the timeout)");
  add(wire::kEmergencyStop, "an emergency stop");
  add(wire::kImuFault, "an IMU fault (no valid reading within the timeout)");
  add(wire::kNoSession, "no session (did it restart?)");
  return out;
}

constexpr int kSessionFaults = wire::kWatchdog | wire::kEmergencyStop | wire::kImuFault | wire::kNoSession;

}  // namespace

BridgePlant::BridgePlant(SerialPort link, BridgeOptions options)
    : BridgePlant(std::make_unique<SerialPort>(std::move(link)), nullptr, options) {}

BridgePlant::BridgePlant(std::unique_ptr<Link> link, const Clock& clock, BridgeOptions options)
    : BridgePlant(std::move(link), &clock, options) {}

BridgePlant::BridgePlant(std::unique_ptr<Link> link, const Clock* clock, BridgeOptions options)
    : link_(std::move(link)),
      clock_(clock ? *clock : steady_clock_),
      epoch_s_(clock_.now_s()),
      options_(options),
      gate_(options.limits) {
  if (options_.limits.max_dkpa <= 0 || options_.limits.rate_dkpa_s <= 0 || options_.limits.timeout_ms == 0) {
    throw std::invalid_argument("bridge: the pressure limit, rate limit and timeout must be positive");
  }
}

BridgePlant::~BridgePlant() {
  if (link_lost_) return;
  try {
    send(wire::kStopPacket, nullptr, 0);
  } catch (...) {  // the device's own watchdog vents when this does not arrive
  }
}

uint32_t BridgePlant::now_ms() const { return static_cast<uint32_t>(std::floor(1000.0 * time_s())); }

double BridgePlant::time_s() const { return clock_.now_s() - epoch_s_; }

double BridgePlant::max_pressure_kpa() const { return gate_.limits().max_dkpa / 10.0; }

void BridgePlant::send(char type, const int32_t* fields, int count) {
  wire::Packet p{};
  p.type = type;
  p.seq = host_seq_++;
  p.count = static_cast<uint8_t>(count);
  for (int i = 0; i < count; ++i) p.fields[i] = fields[i];
  char buffer[wire::kMaxLine + 2];
  const std::size_t n = wire::format_packet(p, buffer, sizeof buffer);
  try {
    link_->write_all(buffer, n);
  } catch (const std::runtime_error& e) {
    link_lost_ = true;
    session_ = false;
    throw BridgeFault(
        fmt::format("link lost: {}; the device's watchdog vents within {} ms", e.what(), gate_.limits().timeout_ms));
  }
}

void BridgePlant::fault(const std::string& cause) {
  session_ = false;
  if (link_lost_) {
    throw BridgeFault(fmt::format("{}: {}; the device's watchdog vents within {} ms", link_->name(), cause,
                                  gate_.limits().timeout_ms));
  }
  try {
    send(wire::kStopPacket, nullptr, 0);
  } catch (const BridgeFault&) {
    throw BridgeFault(fmt::format("{}: {}; the link is gone too, the device's watchdog vents within {} ms",
                                  link_->name(), cause, gate_.limits().timeout_ms));
  }
  throw BridgeFault(fmt::format("{}: {}; vented (emergency stop sent)", link_->name(), cause));
}

void BridgePlant::pump(int timeout_ms) {
  if (link_lost_) fault("the link is lost");
  char buffer[512];
  std::size_t n = 0;
  try {
    n = link_->read_some(buffer, sizeof buffer, timeout_ms);
  } catch (const std::runtime_error& e) {
    link_lost_ = true;
    fault(fmt::format("link lost ({})", e.what()));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (lines_.push(buffer[i])) handle_line(lines_.line(), lines_.length());
  }
  stats_.overlong_lines = lines_.dropped();
}

void BridgePlant::handle_line(const char* line, std::size_t length) {
  switch (protocol_.handle_line(line, length)) {
    case DeviceLine::kGarbled:
      ++stats_.garbled_from_device;
      break;
    case DeviceLine::kOutOfSequence:
      ++stats_.out_of_sequence;
      break;
    case DeviceLine::kRejection:
      ++stats_.rejected_by_device;
      break;
    case DeviceLine::kAnswer:
      answered_ = true;
      break;
    case DeviceLine::kData:
      handle_data(protocol_.data());
      break;
  }
}

void BridgePlant::handle_data(const DeviceData& data) {
  const uint32_t now = now_ms();
  if (session_ && have_data_) stats_.max_data_gap_s = std::max(stats_.max_data_gap_s, (now - data_ms_) / 1000.0);
  have_data_ = true;
  data_ms_ = now;
  data_ = data;
  ++stats_.data_received;
  gate_.imu_reading(!(data.flags & wire::kImuFault), now);
  if (session_ && (data.flags & kSessionFaults))
    fault(fmt::format("the device reports {}", describe_flags(data.flags)));
}

DeviceInfo BridgePlant::start_session() {
  session_ = false;
  answered_ = false;
  const double deadline = time_s() + options_.handshake_timeout_s;
  double next_hello = time_s();
  while (!answered_) {
    const double now = time_s();
    if (now >= deadline) {
      throw BridgeFault(
          fmt::format("{}: no answer to hello within {} s (is the softwrist firmware or emulator "
                      "on the other end, at 115200 baud?)",
                      link_->name(), options_.handshake_timeout_s));
    }
    if (now >= next_hello) {
      const int32_t version = wire::kProtocolVersion;
      send(wire::kHelloPacket, &version, 1);
      next_hello = now + options_.hello_interval_s;
    }
    pump(static_cast<int>(std::ceil(1000.0 * std::min(next_hello, deadline) - 1000.0 * now)));
  }
  const DeviceInfo& device = protocol_.device();
  if (device.version != wire::kProtocolVersion) {
    throw BridgeFault(fmt::format("{}: the device speaks protocol version {}, this softwrist version {}", link_->name(),
                                  device.version, wire::kProtocolVersion));
  }
  if (device.limits.max_dkpa <= 0 || device.limits.rate_dkpa_s <= 0 || device.limits.timeout_ms == 0) {
    fault("the device announced limits that are not positive");
  }
  gate_ = wire::SafetyGate(stricter(options_.limits, device.limits));
  const uint32_t start = now_ms();
  gate_.start_session(start);
  have_data_ = false;
  session_ = true;
  // Every data packet after the answer reflects the new session; the first valid one opens it.
  while (!have_data_) {
    if (now_ms() - start > gate_.limits().timeout_ms * 5) fault("no data after the hello's answer");
    pump(5);
  }
  return device;
}

void BridgePlant::end_session() {
  session_ = false;
  if (!link_lost_) send(wire::kStopPacket, nullptr, 0);
}

void BridgePlant::check_data_fresh() {
  if (!session_) return;
  const uint32_t age = now_ms() - data_ms_;
  if (age > gate_.limits().timeout_ms) {
    fault(
        fmt::format("no valid data from the device for {} ms (timeout {} ms): the link cut, the device stalled "
                    "or garbage on the line",
                    age, gate_.limits().timeout_ms));
  }
}

void BridgePlant::command_pressures_kpa(const control::Pressures& pressures) {
  if (!session_) throw std::logic_error("bridge: a command outside a session (start_session first)");
  for (std::size_t i = 0; i < 4; ++i) {
    if (!(pressures[i] >= 0.0 && pressures[i] <= max_pressure_kpa())) {
      fault(fmt::format("a command of {} kPa for the {} is outside 0-{} kPa", pressures[i], control::kMuscleNames[i],
                        max_pressure_kpa()));
    }
  }
  pump(0);
  check_data_fresh();
  int32_t requested[4], output[4];
  for (std::size_t i = 0; i < 4; ++i) requested[i] = static_cast<int32_t>(std::lround(pressures[i] * 10.0));
  const uint32_t now = now_ms();
  const uint32_t since_command = now - last_command_ms_;
  gate_.command(requested, now);
  gate_.update(now, output);
  if (gate_.flags(now) & wire::kWatchdog) {
    fault(fmt::format("this process stalled: {} ms since its last command (timeout {} ms)", since_command,
                      gate_.limits().timeout_ms));
  }
  last_command_ms_ = now;
  send(wire::kSetPacket, output, 4);
  ++stats_.commands_sent;
}

control::ImuReading BridgePlant::read_angles() {
  control::ImuReading r;
  if (!have_data_) return r;
  r.angles = {.fe_deg = data_.fe_cdeg / 100.0, .ur_deg = data_.ur_cdeg / 100.0};
  r.time_s = data_ms_ / 1000.0;
  r.valid = !(data_.flags & wire::kImuFault) && now_ms() - data_ms_ <= gate_.limits().timeout_ms;
  return r;
}

control::Pressures BridgePlant::measured_pressures_kpa() const {
  control::Pressures p{};
  for (std::size_t i = 0; i < 4; ++i) p[i] = data_.measured_dkpa[i] / 10.0;
  return p;
}

void BridgePlant::wait_until(double t) {
  pump(0);
  check_data_fresh();
  for (double now = time_s(); now < t; now = time_s()) {
    pump(std::clamp(static_cast<int>(std::ceil((t - now) * 1000.0)), 0, 5));
    check_data_fresh();
  }
}

}  // namespace softwrist::bridge
