#include "common/publish_latency.h"

#include "common/bus.h"
#include "common/channels.h"
#include "common/time_base.h"

namespace nadir {

void note_publish_latency(const std::string& channel, const uint8_t* data, size_t size, LatencyWindow* window) {
  if (channels::is_bookkeeping(channel)) return;
  int64_t utime = 0;
  if (encoded_utime(data, size, &utime)) window->add_ms(static_cast<double>(vehicle_time_now_us() - utime) / 1000.0);
}

}  // namespace nadir
