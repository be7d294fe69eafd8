#include "common/shutdown.h"

#include <csignal>
#include <cstdlib>
#include <unistd.h>

namespace nadir {
namespace {
volatile std::sig_atomic_t g_stop = 0;

void on_signal(int) {
  if (g_stop) _exit(130);  // second signal: the user means it
  g_stop = 1;
}
}  // namespace

void install_shutdown_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}

bool shutdown_requested() { return g_stop != 0; }
void request_shutdown() { g_stop = 1; }

}  // namespace nadir
