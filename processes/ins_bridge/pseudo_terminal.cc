#include "processes/ins_bridge/pseudo_terminal.h"

#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace nadir::ins_bridge {

PseudoTerminal::PseudoTerminal(const std::string& link_path) : link_path_(link_path) {
  master_ = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master_ < 0) throw std::runtime_error(std::string("posix_openpt: ") + std::strerror(errno));
  char name[128];
  if (grantpt(master_) != 0 || unlockpt(master_) != 0 || ptsname_r(master_, name, sizeof name) != 0) {
    const std::string why = std::strerror(errno);
    ::close(master_);
    throw std::runtime_error("pseudo-terminal setup: " + why);
  }
  slave_path_ = name;
  slave_keep_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
  termios tio{};
  if (slave_keep_ < 0 || tcgetattr(slave_keep_, &tio) != 0) {
    const std::string why = std::strerror(errno);
    close();
    throw std::runtime_error(slave_path_ + ": " + why);
  }
  cfmakeraw(&tio);
  tcsetattr(slave_keep_, TCSANOW, &tio);
  // A full pty must not block the writer: a real line drops bytes too.
  fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
  if (!link_path_.empty()) {
    const std::string temp = link_path_ + ".new";
    ::unlink(temp.c_str());
    if (::symlink(slave_path_.c_str(), temp.c_str()) != 0 || ::rename(temp.c_str(), link_path_.c_str()) != 0) {
      const std::string why = std::strerror(errno);
      close();
      throw std::runtime_error(link_path_ + ": cannot link to " + slave_path_ + ": " + why);
    }
  }
}

PseudoTerminal::~PseudoTerminal() { close(); }

void PseudoTerminal::close() {
  if (master_ >= 0 && !link_path_.empty()) {
    // Unplugged: the link goes as a udev link does. Left dangling it would
    // point at whatever pty next gets this number (another process's device).
    // Only while it is still ours: a replacement may already have taken it.
    char target[256];
    const ssize_t n = ::readlink(link_path_.c_str(), target, sizeof target - 1);
    if (n > 0 && std::string(target, static_cast<size_t>(n)) == slave_path_) ::unlink(link_path_.c_str());
  }
  if (slave_keep_ >= 0) ::close(slave_keep_);
  if (master_ >= 0) ::close(master_);
  slave_keep_ = master_ = -1;
}

size_t PseudoTerminal::write(const void* data, size_t size) {
  size_t done = 0;
  const auto* bytes = static_cast<const uint8_t*>(data);
  while (master_ >= 0 && done < size) {
    const ssize_t n = ::write(master_, bytes + done, size - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      break;  // full (EAGAIN) or gone
    }
  }
  return done;
}

}  // namespace nadir::ins_bridge
