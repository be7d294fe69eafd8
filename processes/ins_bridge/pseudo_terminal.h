#pragma once
// A pseudo-terminal pair standing in for a serial cable: the simulator and the
// tests write device bytes into the master; the bridge opens the slave path
// (or a symlink to it) exactly like /dev/ttyUSB0.

#include <string>

namespace nadir::ins_bridge {

class PseudoTerminal {
 public:
  // Creates the pair, puts the slave in raw mode (no echo, no line editing)
  // and, when link_path is not empty, points a symlink there (replaced
  // atomically). Throws std::runtime_error naming what failed.
  explicit PseudoTerminal(const std::string& link_path = "");
  ~PseudoTerminal();
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  // Writes all bytes unless the pty is full (the reader is not keeping up);
  // returns the number written.
  size_t write(const void* data, size_t size);
  int master_fd() const { return master_; }
  const std::string& slave_path() const { return slave_path_; }
  // The path to open: the symlink if one was asked for, else the slave.
  const std::string& path() const { return link_path_.empty() ? slave_path_ : link_path_; }
  // Closes the master: the device is "unplugged" (readers see a hangup) and
  // the symlink, while it still points here, is removed.
  void close();

 private:
  int master_ = -1;
  int slave_keep_ = -1;  // keeps the raw termios and the pty alive between readers
  std::string slave_path_;
  std::string link_path_;
};

}  // namespace nadir::ins_bridge
