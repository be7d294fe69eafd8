#include "common/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "common/time_base.h"

namespace nadir {

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::string label, double total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled), start_us_(monotonic_now_us()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(double done) {
  if (!enabled_ || finished_) return;
  const int64_t now = monotonic_now_us();
  if (now - last_draw_us_ < 100000 && done < total_) return;
  last_draw_us_ = now;
  const double fraction = total_ > 0 ? std::clamp(done / total_, 0.0, 1.0) : 0.0;
  const int width = 40;
  const int filled = static_cast<int>(fraction * width);
  const double elapsed = us_to_s(now - start_us_);
  const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
  std::fprintf(stderr, "\r%s [%.*s%*s] %5.1f%%  %.0fs elapsed, %.0fs left ", label_.c_str(), filled,
               "========================================", width - filled, "", fraction * 100, elapsed, eta);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  update(total_);
  finished_ = true;
  std::fprintf(stderr, "\n");
}

}  // namespace nadir
