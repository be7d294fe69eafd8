#include "common/serial_port.h"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace nadir {

double SerialOptions::byte_time_us() const {
  const int bits = 1 + data_bits + (parity == "none" ? 0 : 1) + stop_bits;
  return bits * 1e6 / baud;
}

SerialOptions SerialOptions::from_config(const Config& s, const SerialOptions& d) {
  SerialOptions o;
  o.device = s.get<std::string>("device", d.device);
  o.baud = s.get<int>("baud", d.baud);
  o.data_bits = s.get<int>("data_bits", d.data_bits);
  o.parity = s.get<std::string>("parity", d.parity);
  o.stop_bits = s.get<int>("stop_bits", d.stop_bits);
  o.flow_control = s.get<std::string>("flow_control", d.flow_control);
  o.stall_timeout_s = s.get<double>("stall_timeout_s", d.stall_timeout_s);
  o.reopen_min_s = s.get<double>("reopen_min_s", d.reopen_min_s);
  o.reopen_max_s = s.get<double>("reopen_max_s", d.reopen_max_s);
  o.absent_poll_s = s.get<double>("absent_poll_s", d.absent_poll_s);
  return o;
}

void SerialOptions::Check(const std::string& source, const std::string& key) const {
  static const int kBauds[] = {1200,   2400,   4800,   9600,    19200,   38400,   57600,  115200,
                               230400, 460800, 500000, 576000, 921600, 1000000, 2000000, 4000000};
  bool baud_ok = false;
  for (int b : kBauds) baud_ok |= b == baud;
  require_option(!device.empty(), source, key + ".device", "must name a serial device");
  require_option(baud_ok, source, key + ".baud",
                 "= " + std::to_string(baud) + " is not a standard rate (1200 .. 4000000, e.g. 115200, 230400)");
  require_option(data_bits >= 5 && data_bits <= 8, source, key + ".data_bits", "must be in [5, 8]");
  require_option(parity == "none" || parity == "even" || parity == "odd", source, key + ".parity",
                 "= '" + parity + "' must be none, even or odd");
  require_option(stop_bits == 1 || stop_bits == 2, source, key + ".stop_bits", "must be 1 or 2");
  require_option(flow_control == "none" || flow_control == "rtscts" || flow_control == "xonxoff", source,
                 key + ".flow_control", "= '" + flow_control + "' must be none, rtscts or xonxoff");
  require_option(stall_timeout_s >= 0.05 && stall_timeout_s <= 600, source, key + ".stall_timeout_s",
                 "must be in [0.05, 600]");
  require_option(reopen_min_s >= 0.01 && reopen_min_s <= 60, source, key + ".reopen_min_s", "must be in [0.01, 60]");
  require_option(reopen_max_s >= reopen_min_s && reopen_max_s <= 600, source, key + ".reopen_max_s",
                 "must be in [reopen_min_s, 600]");
  require_option(absent_poll_s >= 0.01 && absent_poll_s <= 10, source, key + ".absent_poll_s", "must be in [0.01, 10]");
}


bool baud_to_speed(int baud, unsigned* speed) {
  switch (baud) {
    case 1200: *speed = B1200; return true;
    case 2400: *speed = B2400; return true;
    case 4800: *speed = B4800; return true;
    case 9600: *speed = B9600; return true;
    case 19200: *speed = B19200; return true;
    case 38400: *speed = B38400; return true;
    case 57600: *speed = B57600; return true;
    case 115200: *speed = B115200; return true;
    case 230400: *speed = B230400; return true;
    case 460800: *speed = B460800; return true;
    case 500000: *speed = B500000; return true;
    case 576000: *speed = B576000; return true;
    case 921600: *speed = B921600; return true;
    case 1000000: *speed = B1000000; return true;
    case 2000000: *speed = B2000000; return true;
    case 4000000: *speed = B4000000; return true;
    default: return false;
  }
}

SerialPort::OpenResult SerialPort::open(std::string* error) {
  close();
  const int fd = ::open(options_.device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int why = errno;
    *error = options_.device + ": open: " + std::strerror(why);
    return why == ENOENT || why == ENODEV || why == ENXIO ? OpenResult::kAbsent : OpenResult::kFailed;
  }
  termios tio{};
  if (tcgetattr(fd, &tio) != 0) {
    *error = options_.device + ": not a terminal: " + std::strerror(errno);
    ::close(fd);
    return OpenResult::kFailed;
  }
  cfmakeraw(&tio);
  unsigned speed = 0;
  baud_to_speed(options_.baud, &speed);  // checked by SerialOptions::Check
  cfsetispeed(&tio, speed);
  cfsetospeed(&tio, speed);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~static_cast<tcflag_t>(CSIZE);
  tio.c_cflag |= options_.data_bits == 5 ? CS5 : options_.data_bits == 6 ? CS6 : options_.data_bits == 7 ? CS7 : CS8;
  tio.c_cflag &= ~static_cast<tcflag_t>(PARENB | PARODD | CSTOPB | CRTSCTS);
  if (options_.parity != "none") tio.c_cflag |= PARENB;
  if (options_.parity == "odd") tio.c_cflag |= PARODD;
  if (options_.stop_bits == 2) tio.c_cflag |= CSTOPB;
  if (options_.flow_control == "rtscts") tio.c_cflag |= CRTSCTS;
  if (options_.flow_control == "xonxoff") tio.c_iflag |= IXON | IXOFF;
  // Parity errors arrive as bytes the parsers reject by CRC/syntax.
  if (options_.parity != "none") tio.c_iflag |= INPCK;
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (tcsetattr(fd, TCSANOW, &tio) != 0) {
    *error = options_.device + ": tcsetattr: " + std::strerror(errno);
    ::close(fd);
    return OpenResult::kFailed;
  }
  fd_ = fd;
  return OpenResult::kOpened;
}

void SerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

SerialPort::ReadResult SerialPort::read_some(uint8_t* buffer, size_t capacity, size_t* got, std::string* error) {
  *got = 0;
  const ssize_t n = ::read(fd_, buffer, capacity);
  if (n > 0) {
    *got = static_cast<size_t>(n);
    return ReadResult::kData;
  }
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return ReadResult::kNothing;
  *error = options_.device + (n == 0 ? ": end of file (device gone)" : std::string(": read: ") + std::strerror(errno));
  return ReadResult::kHangup;
}

}  // namespace nadir
