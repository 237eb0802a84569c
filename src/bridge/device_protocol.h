#pragma once
// The device's side of the line protocol (docs/bridge-protocol.md): what the firmware and the device emulator do
// with each line from the host, and the data packet they send every 10 ms. One implementation for both, so the
// emulator the bridge is tested against behaves as the firmware does. Freestanding C++11 like wire_format.h.

#include <stddef.h>
#include <stdint.h>

#include "safety_gate.h"
#include "wire_format.h"

namespace softwrist {
namespace wire {

class DeviceProtocol {
 public:
  explicit DeviceProtocol(SafetyGate* gate) : gate_(gate), host_seq_(0), device_seq_(0), host_seq_seen_(false) {}

  // Handles one line from the host at `now_ms`. Returns the type of the packet acted on (kHelloPacket, kSetPacket or
  // kStopPacket), or 0 when the line was rejected. Writes the answer to send into `reply` (V for a hello, R for a
  // rejection) and sets
  // `*has_reply`.
  char handle_line(const char* line, size_t length, uint32_t now_ms, Packet* reply, bool* has_reply) {
    *has_reply = true;
    Packet p;
    const ParseError error = parse_line(line, length, &p);
    if (error != kOk) return reject(error, reply);
    if (p.type != kHelloPacket && p.type != kSetPacket && p.type != kStopPacket) return reject(kUnknownType, reply);
    // A hello may restart the count (a new host process); anything else must be newer than the last packet.
    if (p.type != kHelloPacket && host_seq_seen_ && !is_newer(p.seq, host_seq_)) return reject(kOutOfSequence, reply);
    if (p.type == kHelloPacket && p.fields[0] != kProtocolVersion) return reject(kOutOfRange, reply);
    host_seq_ = p.seq;
    host_seq_seen_ = true;
    *has_reply = false;
    if (p.type == kHelloPacket) {
      gate_->start_session(now_ms);
      reply->type = kHelloReplyPacket;
      reply->seq = device_seq_++;
      reply->count = 4;
      reply->fields[0] = kProtocolVersion;
      reply->fields[1] = gate_->limits().max_dkpa;
      reply->fields[2] = gate_->limits().rate_dkpa_s;
      reply->fields[3] = static_cast<int32_t>(gate_->limits().timeout_ms);
      *has_reply = true;
    } else if (p.type == kSetPacket) {
      gate_->command(p.fields, now_ms);
    } else {
      gate_->emergency_stop();
    }
    return p.type;
  }

  // The 100 Hz data packet: the IMU pair's wrist angles [0.01 deg], the measured pressures [dkPa], the status.
  Packet data_packet(uint32_t now_ms, int32_t fe_cdeg, int32_t ur_cdeg, const int32_t measured_dkpa[4]) {
    Packet d;
    d.type = kDataPacket;
    d.seq = device_seq_++;
    d.count = 8;
    d.fields[0] = static_cast<int32_t>(now_ms);
    d.fields[1] = fe_cdeg;
    d.fields[2] = ur_cdeg;
    for (int i = 0; i < 4; ++i) d.fields[3 + i] = measured_dkpa[i];
    d.fields[7] = gate_->flags(now_ms);
    return d;
  }

 private:
  char reject(uint8_t reason, Packet* reply) {
    reply->type = kRejectPacket;
    reply->seq = device_seq_++;
    reply->count = 1;
    reply->fields[0] = reason;
    return 0;
  }

  SafetyGate* gate_;
  uint16_t host_seq_, device_seq_;
  bool host_seq_seen_;
};

}  // namespace wire
}  // namespace softwrist
