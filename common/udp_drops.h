#pragma once
// Datagrams the kernel threw away because this process's UDP receive buffer
// was full. LCM reads its socket in its own thread and never learns of such
// losses; a process that was stopped (SIGSTOP, a debugger, swap) or starved
// loses messages there without a trace. Linux counts them per socket in the
// last column ("drops") of /proc/net/udp; this sums that column over the
// sockets this process has open.

#include <cstdint>

namespace nadir {

// Sum of the kernel's receive drops over this process's UDP sockets (IPv4
// and IPv6) bound to local_port (0: every socket), or -1 when /proc cannot
// tell (not Linux, /proc not mounted). A bus counts its own port only: a
// process may hold other UDP sockets (a GigE Vision stream, a MAVLink link)
// whose drops are not lost bus messages.
int64_t own_udp_receive_drops(int local_port = 0);

}  // namespace nadir
