#pragma once
// The bridge's line protocol (docs/bridge-protocol.md), shared word for word by the host (src/bridge), the device
// emulator and the Arduino firmware (firmware/): freestanding C++11 (no allocation, no exceptions, no standard
// library beyond <stdint.h> and <stddef.h>), so that avr-gcc compiles the same parser the host is tested with.
//
// A packet is one ASCII line: TYPE SEQ FIELD... *CC\n
//   TYPE   one letter (below); SEQ a 16-bit sequence number, counted per sender and direction;
//   FIELD  signed decimal integers in fixed-point units: pressures in 0.1 kPa (dkPa), angles in 0.01 deg, time in ms;
//   CC     CRC-8 (polynomial 0x07, initial 0) of every byte before the '*', two upper-case hex digits.
// Host to device:  H seq version              hello: start or resume a session (clears an emergency stop)
//                  S seq p0 p1 p2 p3          set the four regulators (flexor, extensor, ulnar, radial) [dkPa]
//                  E seq                      emergency stop: vent and stay vented until the next hello
// Device to host:  V seq version max_dkpa rate_dkpa_s timeout_ms   hello's answer: the device's safety settings
//                  D seq t_ms fe_cdeg ur_cdeg m0 m1 m2 m3 flags     100 Hz data: IMU wrist angles, measured pressures
//                  R seq reason                                     a packet was rejected (reason: ParseError or 16+)

#include <stddef.h>
#include <stdint.h>

namespace softwrist {
namespace wire {

const int kProtocolVersion = 1;

// Packet types: the TYPE letter of each packet above.
const char kHelloPacket = 'H';       // host to device
const char kSetPacket = 'S';         // host to device
const char kStopPacket = 'E';        // host to device: emergency stop
const char kHelloReplyPacket = 'V';  // device to host
const char kDataPacket = 'D';        // device to host
const char kRejectPacket = 'R';      // device to host
const size_t kMaxLine = 96;          // longer lines are garbage
const int kMaxFields = 9;

// Device status flags in a D packet.
enum StatusFlag : int32_t {
  kVented = 1,         // all regulators at 0 (vented) and the supply valve closed
  kEmergencyStop = 2,  // latched by an E packet until the next hello
  kWatchdog = 4,       // the watchdog vented (no valid S packet or IMU reading within the timeout); latched
  kImuFault = 8,       // the IMUs gave no valid reading within the timeout (the device vents too)
  kLimited = 16,       // the last command was clamped to the pressure limit or slowed by the rate limit
  kNoSession = 32,     // no hello yet
};

enum ParseError : uint8_t {
  kOk = 0,
  kTooLong = 1,
  kNoChecksum = 2,
  kBadChecksum = 3,
  kUnknownType = 4,
  kBadNumber = 5,
  kWrongFieldCount = 6,
  kOutOfSequence = 7,  // reported by the receiver, not by parse_line
  kOutOfRange = 8,     // a field outside its range (a pressure below 0, say)
};

struct Packet {
  char type;
  uint16_t seq;
  uint8_t count;  // fields after seq
  int32_t fields[kMaxFields];
};

// The number of fields after SEQ for each type, or -1 for an unknown type.
inline int field_count(char type) {
  switch (type) {
    case kHelloPacket:
      return 1;
    case kSetPacket:
      return 4;
    case kStopPacket:
      return 0;
    case kHelloReplyPacket:
      return 4;
    case kDataPacket:
      return 8;
    case kRejectPacket:
      return 1;
    default:
      return -1;
  }
}

inline uint8_t crc8(const char* data, size_t length) {
  uint8_t crc = 0;
  for (size_t i = 0; i < length; ++i) {
    crc = static_cast<uint8_t>(crc ^ static_cast<uint8_t>(data[i]));
    for (int bit = 0; bit < 8; ++bit) crc = static_cast<uint8_t>((crc & 0x80) ? (crc << 1) ^ 0x07 : crc << 1);
  }
  return crc;
}

// True when `seq` comes after `last` (modulo 2^16, within half the range): a repeated or older packet is not.
inline bool is_newer(uint16_t seq, uint16_t last) {
  return static_cast<uint16_t>(seq - last) != 0 && static_cast<uint16_t>(seq - last) < 0x8000;
}

namespace detail {
inline int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}
// Parses a signed decimal integer of at most 10 digits from [*at, end); stops at a space or the end.
inline bool parse_int(const char*& at, const char* end, int32_t* value) {
  bool negative = false;
  if (at < end && *at == '-') {
    negative = true;
    ++at;
  }
  int64_t v = 0;
  int digits = 0;
  while (at < end && *at != ' ') {
    if (*at < '0' || *at > '9' || ++digits > 10) return false;
    v = v * 10 + (*at - '0');
    ++at;
  }
  if (digits == 0) return false;
  if (negative) v = -v;
  if (v < -2147483647LL || v > 2147483647LL) return false;
  *value = static_cast<int32_t>(v);
  return true;
}
}  // namespace detail

// Parses one line (without its '\n'; a trailing '\r' is allowed). Checks the checksum first, so a garbled line is
// reported as such and nothing in it is trusted.
inline ParseError parse_line(const char* line, size_t length, Packet* out) {
  if (length > 0 && line[length - 1] == '\r') --length;
  if (length > kMaxLine) return kTooLong;
  if (length < 4 || line[length - 3] != '*') return kNoChecksum;
  const int high = detail::hex_value(line[length - 2]), low = detail::hex_value(line[length - 1]);
  if (high < 0 || low < 0) return kNoChecksum;
  const size_t body = length - 3;
  if (crc8(line, body) != static_cast<uint8_t>(high * 16 + low)) return kBadChecksum;
  // The body: TYPE ' ' SEQ (' ' FIELD)* ' '
  if (body < 4 || line[1] != ' ' || line[body - 1] != ' ') return kWrongFieldCount;
  const int expected = field_count(line[0]);
  if (expected < 0) return kUnknownType;
  const char* at = line + 2;
  const char* end = line + body - 1;
  int32_t seq = 0;
  if (!detail::parse_int(at, end, &seq)) return kBadNumber;
  if (seq < 0 || seq > 65535) return kOutOfRange;
  Packet p;
  p.type = line[0];
  p.seq = static_cast<uint16_t>(seq);
  p.count = 0;
  while (at < end) {
    ++at;  // the space
    if (p.count == kMaxFields) return kWrongFieldCount;
    if (!detail::parse_int(at, end, &p.fields[p.count])) return kBadNumber;
    ++p.count;
  }
  if (p.count != expected) return kWrongFieldCount;
  *out = p;
  return kOk;
}

// Writes the packet's line with its checksum and '\n' into `buffer`; returns its length, or 0 when it does not fit
// or the field count is wrong for the type.
inline size_t format_packet(const Packet& p, char* buffer, size_t size) {
  if (field_count(p.type) != p.count || size < kMaxLine + 2) return 0;
  size_t n = 0;
  const auto put_int = [&](int32_t value) {
    // 32-bit, and 16-bit once the rest fits: on the AVR a 64-bit division per digit made a data packet cost 3 ms of
    // the firmware's loop (measured on the firmware in the loop, docs/hil.md).
    char digits[12];
    int count = 0;
    uint32_t v = value < 0 ? 0u - static_cast<uint32_t>(value) : static_cast<uint32_t>(value);
    if (value < 0) buffer[n++] = '-';
    while (v > 0xFFFFu) {
      digits[count++] = static_cast<char>('0' + v % 10u);
      v /= 10u;
    }
    uint16_t w = static_cast<uint16_t>(v);
    do {
      digits[count++] = static_cast<char>('0' + w % 10u);
      w = static_cast<uint16_t>(w / 10u);
    } while (w > 0);
    while (count > 0) buffer[n++] = digits[--count];
    buffer[n++] = ' ';
  };
  buffer[n++] = p.type;
  buffer[n++] = ' ';
  put_int(p.seq);
  for (int i = 0; i < p.count; ++i) put_int(p.fields[i]);
  const uint8_t crc = crc8(buffer, n);
  const char* hex = "0123456789ABCDEF";
  buffer[n++] = '*';
  buffer[n++] = hex[crc >> 4];
  buffer[n++] = hex[crc & 0x0F];
  buffer[n++] = '\n';
  return n;
}

// Splits a byte stream into lines. A line longer than kMaxLine is dropped whole (up to its '\n') and counted.
class LineAssembler {
 public:
  LineAssembler() : length_(0), ready_(0), overflowed_(false), dropped_(0) {}
  // Feeds one byte; returns true when a complete line is in line()/length(), valid until the next push.
  bool push(char c) {
    if (c == '\n') {
      const bool complete = !overflowed_;
      if (overflowed_) ++dropped_;
      overflowed_ = false;
      ready_ = length_;
      length_ = 0;
      return complete;
    }
    if (length_ >= kMaxLine) {
      overflowed_ = true;
      return false;
    }
    buffer_[length_++] = c;
    return false;
  }
  const char* line() const { return buffer_; }
  size_t length() const { return ready_; }
  uint32_t dropped() const { return dropped_; }

 private:
  char buffer_[kMaxLine + 1];
  size_t length_;
  size_t ready_;
  bool overflowed_;
  uint32_t dropped_;
};

}  // namespace wire
}  // namespace softwrist
