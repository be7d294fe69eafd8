#pragma once
// One serial device opened with termios: raw 8-bit input, the configured
// baud, parity, stop bits and flow control, non-blocking so that one device
// can never hold up the other.

#include <sys/types.h>

#include <cstdint>
#include <string>

#include "common/config.h"
#include "common/options_schema.h"

namespace nadir {

// A serial device's settings, e.g. the `ins_bridge.ins.serial:` section.
struct SerialOptions {
  std::string device;            // path, e.g. /dev/ttyUSB0 or a pty symlink
  int baud = 115200;
  int data_bits = 8;             // 5..8
  std::string parity = "none";   // none | even | odd
  int stop_bits = 1;             // 1 | 2
  std::string flow_control = "none";  // none | rtscts | xonxoff
  double stall_timeout_s = 1.0;  // no byte for this long: stall, reopen
  double reopen_min_s = 0.1;     // reopen delay after a hangup/stall; doubles per failed open of a present device
  double reopen_max_s = 5.0;     // backoff cap
  double absent_poll_s = 0.1;    // while the path does not exist (unplugged): fixed poll, no backoff
  // Seconds one character takes on the line (start + data + parity + stop bits).
  double byte_time_us() const;
  static SerialOptions from_config(const Config& section, const SerialOptions& defaults);
  void Check(const std::string& source, const std::string& key) const;
  // The keys of a serial line's section (options_schema.h).
  static const OptionsSchema<SerialOptions>& schema();
};


class SerialPort {
 public:
  explicit SerialPort(SerialOptions options) : options_(std::move(options)) {}
  ~SerialPort() { close(); }
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  enum class OpenResult { kOpened, kAbsent, kFailed };
  // Opens and configures the device. kAbsent: nothing at the path (unplugged:
  // no such file, a dangling link, a node without a device); kFailed: the
  // device is there but cannot be opened or configured. Both with a message
  // naming the device.
  OpenResult open(std::string* error);
  void close();
  bool is_open() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  const SerialOptions& options() const { return options_; }

  enum class ReadResult { kData, kNothing, kHangup };
  // Reads what is waiting. kHangup: the device went away (EOF, EIO, ...).
  ReadResult read_some(uint8_t* buffer, size_t capacity, size_t* got, std::string* error);

 private:
  SerialOptions options_;
  int fd_ = -1;
};

// termios speed constant for a baud rate; false when not supported.
bool baud_to_speed(int baud, unsigned* speed);

}  // namespace nadir
