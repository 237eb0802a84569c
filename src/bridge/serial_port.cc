#include "bridge/serial_port.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace softwrist::bridge {
namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::runtime_error(fmt::format("{}: {}: {}", name, what, std::strerror(errno)));
}

speed_t speed_of(int baud, const std::string& name) {
  switch (baud) {
    case 9600:
      return B9600;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    default:
      throw std::runtime_error(fmt::format("{}: unsupported baud rate {}", name, baud));
  }
}

void make_raw(int fd, speed_t speed, const std::string& name) {
  termios tio{};
  if (tcgetattr(fd, &tio) != 0) fail(name, "not a serial device");
  cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  cfsetispeed(&tio, speed);
  cfsetospeed(&tio, speed);
  if (tcsetattr(fd, TCSANOW, &tio) != 0) fail(name, "cannot configure");
}

}  // namespace

SerialPort SerialPort::Open(const std::filesystem::path& device, int baud) {
  const speed_t speed = speed_of(baud, device.string());
  const int fd = open(device.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) fail(device.string(), "cannot open");
  SerialPort port(fd, device.string());
  make_raw(fd, speed, port.name_);
  tcflush(fd, TCIOFLUSH);  // whatever the device sent before we listened is stale
  return port;
}

SerialPort::SerialPort(int fd, std::string name) : fd_(fd), name_(std::move(name)) { make_raw(fd_, B115200, name_); }

SerialPort::~SerialPort() {
  if (fd_ >= 0) close(fd_);
}

SerialPort::SerialPort(SerialPort&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), name_(std::move(other.name_)) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    name_ = std::move(other.name_);
  }
  return *this;
}

void SerialPort::write_all(const char* data, std::size_t size) {
  // Bounded: a device that stops reading must not hang the host (its watchdog vents while we give up).
  constexpr int kWriteTimeoutMs = 500;
  int waited_ms = 0;
  while (size > 0) {
    const std::size_t n = write_some(data, size);
    if (n == 0) {
      if (waited_ms >= kWriteTimeoutMs) {
        throw std::runtime_error(
            fmt::format("{}: write timed out after {} ms (the other side is not reading)", name_, kWriteTimeoutMs));
      }
      pollfd p{fd_, POLLOUT, 0};
      poll(&p, 1, 10);
      waited_ms += 10;
      continue;
    }
    data += n;
    size -= n;
  }
}

std::size_t SerialPort::write_some(const char* data, std::size_t size) {
  const ssize_t n = write(fd_, data, size);
  if (n >= 0) return static_cast<std::size_t>(n);
  if (errno == EINTR || errno == EAGAIN) return 0;
  fail(name_, "write failed (the link is gone)");
}

std::size_t SerialPort::read_some(char* buffer, std::size_t size, int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = poll(&p, 1, timeout_ms);
  if (ready < 0 && errno == EINTR) return 0;
  if (ready < 0) fail(name_, "poll failed");
  if (ready == 0) return 0;
  const ssize_t n = read(fd_, buffer, size);
  if (n > 0) return static_cast<std::size_t>(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  // End of file, or EIO: the other side has gone (a pseudo-terminal reports its hang-up as EIO).
  throw std::runtime_error(fmt::format("{}: the link is gone", name_));
}

PseudoTerminal PseudoTerminal::Open() {
  const int fd = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) fail("pseudo-terminal", "posix_openpt");
  if (grantpt(fd) != 0 || unlockpt(fd) != 0) {
    close(fd);
    fail("pseudo-terminal", "grantpt/unlockpt");
  }
  char path[128];
  if (ptsname_r(fd, path, sizeof path) != 0) {
    close(fd);
    fail("pseudo-terminal", "ptsname");
  }
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
  return {SerialPort(fd, path), path};
}

}  // namespace softwrist::bridge
