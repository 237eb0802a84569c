#pragma once
// The host's side of the line protocol (docs/bridge-protocol.md): what the bridge accepts from the device, the
// mirror of device_protocol.h. Pure (no I/O, no clock), so that the decoder BridgePlant acts on is the one fuzzed
// (tests/fuzz/host_protocol_fuzz.cc). Garbled, unknown, implausible and out-of-sequence packets are classified and
// dropped here; nothing in them reaches the caller.

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "bridge/safety_gate.h"
#include "bridge/wire_format.h"

namespace softwrist::bridge {

// The device's answer to hello.
struct DeviceInfo {
  int version = 0;
  wire::SafetyLimits limits;
};

// A valid D packet's fields.
struct DeviceData {
  std::int32_t t_ms = 0;
  std::int32_t fe_cdeg = 0, ur_cdeg = 0;  // IMU wrist angles [0.01 deg]
  std::int32_t measured_dkpa[4] = {};     // the regulators' measured pressures [0.1 kPa]
  std::int32_t flags = wire::kNoSession;  // wire::StatusFlag
};

enum class DeviceLine {
  kGarbled,        // checksum, type, field count, numbers or an implausible value: dropped
  kOutOfSequence,  // repeated or stale: dropped
  kRejection,      // R: the device refused one of our packets
  kAnswer,         // V: device() holds the device's version and limits
  kData,           // D: data() holds it
};

class HostProtocol {
 public:
  DeviceLine handle_line(const char* line, std::size_t length) {
    wire::Packet p;
    if (wire::parse_line(line, length, &p) != wire::kOk ||
        (p.type != wire::kHelloReplyPacket && p.type != wire::kDataPacket && p.type != wire::kRejectPacket)) {
      return DeviceLine::kGarbled;
    }
    if (p.type == wire::kDataPacket && !plausible_data(p)) return DeviceLine::kGarbled;
    // A V packet answers our hello and may come from a device that restarted its count; anything else must be newer.
    if (p.type != wire::kHelloReplyPacket && seq_seen_ && !wire::is_newer(p.seq, seq_))
      return DeviceLine::kOutOfSequence;
    seq_ = p.seq;
    seq_seen_ = true;
    if (p.type == wire::kRejectPacket) return DeviceLine::kRejection;
    if (p.type == wire::kHelloReplyPacket) {
      device_.version = p.fields[0];
      device_.limits.max_dkpa = p.fields[1];
      device_.limits.rate_dkpa_s = p.fields[2];
      device_.limits.timeout_ms = static_cast<std::uint32_t>(p.fields[3] > 0 ? p.fields[3] : 0);
      return DeviceLine::kAnswer;
    }
    data_.t_ms = p.fields[0];
    data_.fe_cdeg = p.fields[1];
    data_.ur_cdeg = p.fields[2];
    for (int i = 0; i < 4; ++i) data_.measured_dkpa[i] = p.fields[3 + i];
    data_.flags = p.fields[7];
    return DeviceLine::kData;
  }

  const DeviceInfo& device() const { return device_; }
  const DeviceData& data() const { return data_; }

  // Angles within +-180 deg, pressures within -10..10000 kPa (a sensor's offset below 0 allowed), known flags.
  static bool plausible_data(const wire::Packet& p) {
    bool plausible =
        p.fields[7] >= 0 && p.fields[7] < 64 && std::abs(p.fields[1]) <= 18000 && std::abs(p.fields[2]) <= 18000;
    for (int i = 3; i < 7; ++i) plausible = plausible && p.fields[i] >= -100 && p.fields[i] <= 100000;
    return plausible;
  }

 private:
  DeviceInfo device_;
  DeviceData data_;
  std::uint16_t seq_ = 0;
  bool seq_seen_ = false;
};

}  // namespace softwrist::bridge
