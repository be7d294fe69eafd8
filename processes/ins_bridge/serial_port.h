#pragma once
// One serial device opened with termios: raw 8-bit input, the configured
// baud, parity, stop bits and flow control, non-blocking so that one device
// can never hold up the other.

#include <sys/types.h>

#include <cstdint>
#include <string>

#include "processes/ins_bridge/bridge_options.h"

namespace nadir::ins_bridge {

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

}  // namespace nadir::ins_bridge
