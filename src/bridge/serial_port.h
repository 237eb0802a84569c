#pragma once
// The serial link to the device (the Arduino's USB serial, /dev/ttyACM0) or to the emulator's pseudo-terminal:
// POSIX termios directly, raw 8N1 with no echo and no line-ending translation. Errors name the device.

#include <cstddef>
#include <filesystem>
#include <string>

namespace softwrist::bridge {

class SerialPort {
 public:
  // Opens and configures `device` (raw, 8N1, `baud` of 9600, 57600, 115200 or 230400). Throws std::runtime_error
  // "<device>: <problem>".
  static SerialPort Open(const std::filesystem::path& device, int baud = 115200);
  // Takes ownership of an open descriptor (a pseudo-terminal's master side), made raw.
  SerialPort(int fd, std::string name);
  ~SerialPort();
  SerialPort(SerialPort&& other) noexcept;
  SerialPort& operator=(SerialPort&& other) noexcept;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Writes every byte; throws when the link is gone or the other side has not read for 0.5 s.
  void write_all(const char* data, std::size_t size);
  // Writes what fits now without waiting; returns how many bytes (0: the link's buffer is full). Throws when the
  // link is gone. A device drops what does not fit, as a UART would.
  std::size_t write_some(const char* data, std::size_t size);
  // Waits up to `timeout_ms` for bytes; returns how many were read (0: none in time). Throws when the link is gone
  // (the device unplugged, the emulator closed).
  std::size_t read_some(char* buffer, std::size_t size, int timeout_ms);
  const std::string& name() const { return name_; }

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
