#pragma once
// The serial link to the device (the Arduino's USB serial, /dev/ttyACM0) or to the emulator's pseudo-terminal:
// POSIX termios directly, raw 8N1 with no echo and no line-ending translation. Errors name the device.

#include <cstddef>
#include <filesystem>
#include <string>

#include "bridge/link.h"

namespace softwrist::bridge {

class SerialPort final : public Link {
 public:
  // Opens and configures `device` (raw, 8N1, `baud` of 9600, 57600, 115200 or 230400). Throws std::runtime_error
  // "<device>: <problem>".
  static SerialPort Open(const std::filesystem::path& device, int baud = 115200);
  // Takes ownership of an open descriptor (a pseudo-terminal's master side), made raw.
  SerialPort(int fd, std::string name);
  ~SerialPort() override;
  SerialPort(SerialPort&& other) noexcept;
  SerialPort& operator=(SerialPort&& other) noexcept;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Link (link.h); write_all gives up when the other side has not read for 0.5 s, and "gone" is the device
  // unplugged or the emulator closed.
  void write_all(const char* data, std::size_t size) override;
  std::size_t write_some(const char* data, std::size_t size) override;
  std::size_t read_some(char* buffer, std::size_t size, int timeout_ms) override;
  const std::string& name() const override { return name_; }

 private:
  int fd_ = -1;
  std::string name_;
};

// A pseudo-terminal pair for the emulator: it keeps the master side and gives the path of the slave side, which
// the bridge opens as if it were the device.
struct PseudoTerminal {
  static PseudoTerminal Open();
  SerialPort master;
  std::string slave_path;
};

}  // namespace softwrist::bridge
