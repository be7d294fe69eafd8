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

const OptionsSchema<SerialOptions>& SerialOptions::schema() {
  using O = SerialOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("serial", "A serial line (common/serial_port.h); each bridge gives its own device default.");
    std::vector<std::pair<std::string, int>> bauds;
    for (int b : {1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000, 921600,
                  1000000, 2000000, 4000000}) {
      bauds.emplace_back(std::to_string(b), b);
    }
    s.text("device", "path, e.g. /dev/ttyUSB0 or a pty symlink", &O::device)
        .choice<int>("baud", bauds, "line rate (bit/s)", &O::baud)
        .number("data_bits", 5, 8, "bits", "data bits per character", &O::data_bits)
        .choice<std::string>("parity", {{"none", "none"}, {"even", "even"}, {"odd", "odd"}}, "parity bit",
                             &O::parity)
        .choice<int>("stop_bits", {{"1", 1}, {"2", 2}}, "stop bits", &O::stop_bits)
        .choice<std::string>("flow_control", {{"none", "none"}, {"rtscts", "rtscts"}, {"xonxoff", "xonxoff"}},
                             "flow control", &O::flow_control)
        .number("stall_timeout_s", 0.05, 600.0, "s", "no byte for this long: stall, reopen", &O::stall_timeout_s)
        .number("reopen_min_s", 0.01, 60.0, "s", "reopen delay after a hangup or stall (doubles per failed open)",
                &O::reopen_min_s)
        .number("reopen_max_s", 0.01, 600.0, "s", "backoff cap (at least reopen_min_s)", &O::reopen_max_s)
        .number("absent_poll_s", 0.01, 10.0, "s", "while the path does not exist: fixed poll", &O::absent_poll_s)
        .rule("device", [](const O& o) { return !o.device.empty(); }, "must name a serial device")
        .rule("reopen_max_s", [](const O& o) { return o.reopen_max_s >= o.reopen_min_s; },
              "must be >= reopen_min_s");
    return s;
  }();
  return schema;
}

SerialOptions SerialOptions::from_config(const Config& s, const SerialOptions& d) {
  SerialOptions o = d;
  schema().read(s, &o);
  return o;
}

void SerialOptions::Check(const std::string& source, const std::string& key) const {
  schema().check(*this, Config(YAML::Node(YAML::NodeType::Map), source, key));
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
