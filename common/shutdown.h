#pragma once
// SIGINT/SIGTERM set a flag that main loops poll; a second signal exits at once.

namespace nadir {

void install_shutdown_handlers();
bool shutdown_requested();
void request_shutdown();

}  // namespace nadir
