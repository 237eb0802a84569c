// The serial link (bridge/serial_port.h) over a pseudo-terminal, as the bridge talks to the emulator: raw bytes
// both ways, read timeouts, and clear errors for a missing device and a link that goes away.

#include "bridge/serial_port.h"

#include <optional>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softwrist::bridge {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

std::string read_exactly(SerialPort& port, std::size_t count) {
  std::string got;
  char buffer[64];
  for (int tries = 0; got.size() < count && tries < 100; ++tries) {
    got.append(buffer, port.read_some(buffer, sizeof buffer, 20));
  }
  return got;
}

TEST(SerialPort, RawBytesBothWaysOverAPseudoTerminal) {
  PseudoTerminal pty = PseudoTerminal::Open();
  SerialPort host = SerialPort::Open(pty.slave_path);
  const std::string packet = "S 1 0 1370 0 0 *4A\r\n";  // \r and \n must pass untranslated, nothing echoed
  host.write_all(packet.data(), packet.size());
  EXPECT_EQ(read_exactly(pty.master, packet.size()), packet);
  const std::string reply = "D 9 1 2 3 4 5 6 7 8 *00\n";
  pty.master.write_all(reply.data(), reply.size());
  EXPECT_EQ(read_exactly(host, reply.size()), reply);
  char buffer[8];
  EXPECT_EQ(host.read_some(buffer, sizeof buffer, 10), 0u);  // nothing more: a timeout, not an error
}

TEST(SerialPort, ErrorsNameTheDevice) {
  EXPECT_THAT([] { SerialPort::Open("/dev/softwrist-no-such-device"); },
              ThrowsMessage<std::runtime_error>(HasSubstr("/dev/softwrist-no-such-device: cannot open")));
  EXPECT_THAT([] { SerialPort::Open("/dev/null"); },
              ThrowsMessage<std::runtime_error>(HasSubstr("/dev/null: not a serial device")));
  EXPECT_THAT([] { SerialPort::Open("/dev/null", 1234); },
              ThrowsMessage<std::runtime_error>(HasSubstr("unsupported baud rate 1234")));
  std::optional<SerialPort> host;
  {
    PseudoTerminal pty = PseudoTerminal::Open();
    host.emplace(SerialPort::Open(pty.slave_path));
  }  // the emulator's side closes
  char buffer[8];
  EXPECT_THAT([&] { host->read_some(buffer, sizeof buffer, 100); },
              ThrowsMessage<std::runtime_error>(HasSubstr("the link is gone")));
}

}  // namespace
}  // namespace softwrist::bridge
