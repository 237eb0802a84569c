#pragma once
// The byte stream between the host and the device, as the bridge and the device emulator see it: a serial port
// (serial_port.h; the Arduino's USB serial or the emulator's pseudo-terminal), or the line of a lock-step test rig
// in simulated time (lockstep_link.h). Errors throw std::runtime_error naming the link.

#include <cstddef>
#include <string>

namespace softwrist::bridge {

class Link {
 public:
  virtual ~Link() = default;
  // Writes every byte; throws when the link is gone or the other side has stopped reading.
  virtual void write_all(const char* data, std::size_t size) = 0;
  // Writes what fits now without waiting; returns how many bytes (0: the buffer is full). Throws when the link is
  // gone. A device drops what does not fit, as a UART would.
  virtual std::size_t write_some(const char* data, std::size_t size) = 0;
  // Waits up to `timeout_ms` for bytes; returns how many were read (0: none in time). Throws when the link is gone.
  virtual std::size_t read_some(char* buffer, std::size_t size, int timeout_ms) = 0;
  virtual const std::string& name() const = 0;
};

}  // namespace softwrist::bridge
