// The bridge's line protocol (bridge/wire_format.h, docs/bridge-protocol.md): what is written reads back, and every
// kind of damage is rejected with its reason, never read as a different packet.

#include "bridge/wire_format.h"

#include <cstdio>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

namespace softwrist::wire {
namespace {

std::string format(const Packet& p) {
  char buffer[kMaxLine + 2];
  const size_t n = format_packet(p, buffer, sizeof buffer);
  return std::string(buffer, n);
}

ParseError parse(const std::string& line, Packet* p) { return parse_line(line.data(), line.size(), p); }

// A line with a correct checksum over `body` (which must end with a space).
std::string with_checksum(const std::string& body) {
  char hex[3];
  std::snprintf(hex, sizeof hex, "%02X", crc8(body.data(), body.size()));
  return body + "*" + hex;
}

// docs/bridge-protocol.md: the TYPE letters, which the firmware already in the field speaks.
TEST(WireFormat, PacketTypesAreTheDocumentedLetters) {
  EXPECT_EQ(kHelloPacket, 'H');
  EXPECT_EQ(kSetPacket, 'S');
  EXPECT_EQ(kStopPacket, 'E');
  EXPECT_EQ(kHelloReplyPacket, 'V');
  EXPECT_EQ(kDataPacket, 'D');
  EXPECT_EQ(kRejectPacket, 'R');
}

TEST(WireFormat, PacketsRoundTrip) {
  const Packet set{'S', 65535, 4, {0, 1370, 5, -1}};
  const std::string line = format(set);
  EXPECT_EQ(line.substr(0, 21), "S 65535 0 1370 5 -1 *");
  EXPECT_EQ(line.back(), '\n');
  Packet back{};
  ASSERT_EQ(parse(line.substr(0, line.size() - 1), &back), kOk);
  EXPECT_EQ(back.type, 'S');
  EXPECT_EQ(back.seq, 65535);
  ASSERT_EQ(back.count, 4);
  EXPECT_EQ(back.fields[1], 1370);
  EXPECT_EQ(back.fields[3], -1);
  const Packet data{'D', 7, 8, {123456789, -4500, 1200, 1370, 0, 0, 0, kVented | kWatchdog}};
  ASSERT_EQ(parse(format(data).substr(0, format(data).size() - 1) + "\r", &back), kOk);  // CRLF is fine
  EXPECT_EQ(back.fields[0], 123456789);
  EXPECT_EQ(back.fields[7], kVented | kWatchdog);
  EXPECT_EQ(format(Packet{'S', 1, 3, {}}), "");  // the wrong field count for S is not written
}

TEST(WireFormat, DamagedLinesAreRejectedWithTheirReason) {
  Packet p{};
  std::string good = format(Packet{'S', 12, 4, {100, 200, 300, 400}});
  good.pop_back();
  std::string flipped = good;
  flipped[4] = '9';  // one digit changed in transit
  EXPECT_EQ(parse(flipped, &p), kBadChecksum);
  EXPECT_EQ(parse("S 12 100 200 300 400", &p), kNoChecksum);
  EXPECT_EQ(parse(good.substr(0, good.size() - 1) + "g", &p), kNoChecksum);
  EXPECT_EQ(parse(std::string(200, 'x'), &p), kTooLong);
  EXPECT_EQ(parse(with_checksum("X 1 "), &p), kUnknownType);
  EXPECT_EQ(parse(with_checksum("S 1 100 200 300 "), &p), kWrongFieldCount);
  EXPECT_EQ(parse(with_checksum("S 1 100 200 300 400 500 "), &p), kWrongFieldCount);
  EXPECT_EQ(parse(with_checksum("S 1 100 2x0 300 400 "), &p), kBadNumber);
  EXPECT_EQ(parse(with_checksum("S 1 100  300 400 "), &p), kBadNumber);
  EXPECT_EQ(parse(with_checksum("S 1 99999999999 0 0 0 "), &p), kBadNumber);
  EXPECT_EQ(parse(with_checksum("S 70000 0 0 0 0 "), &p), kOutOfRange);
  EXPECT_EQ(parse(with_checksum("S1 0 0 0 0 "), &p), kWrongFieldCount);
  EXPECT_EQ(parse(with_checksum("E 3 "), &p), kOk);
  EXPECT_EQ(p.type, 'E');
}

TEST(WireFormat, SequenceNumbersWrapAround) {
  EXPECT_TRUE(is_newer(1, 0));
  EXPECT_TRUE(is_newer(0, 65535));
  EXPECT_FALSE(is_newer(5, 5));  // a repeat
  EXPECT_FALSE(is_newer(4, 5));  // older
  EXPECT_FALSE(is_newer(40000, 5));
}

TEST(WireFormat, LineAssemblerDropsOverlongLinesWhole) {
  LineAssembler lines;
  std::string got;
  const std::string stream = "E 1 *00\n" + std::string(150, 'z') + "\nH 2 1 *00\n";
  for (char c : stream) {
    if (lines.push(c)) got += std::string(lines.line(), lines.length()) + "|";
  }
  EXPECT_EQ(got, "E 1 *00|H 2 1 *00|");
  EXPECT_EQ(lines.dropped(), 1u);
}

}  // namespace
}  // namespace softwrist::wire
