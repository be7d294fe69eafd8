#include "common/clock_sync.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/config.h"

namespace nadir {
namespace {

// A block's spread is the largest of ~100 arrivals: the link's worst delay
// lies a little beyond it, and the fitted floor a fraction of a millisecond
// off the true one. A quarter more covers both on uniform and exponential
// jitter alike.
constexpr double kLateBoundMargin = 1.25;

}  // namespace

const OptionsSchema<ClockSyncOptions>& ClockSyncOptions::schema() {
  using O = ClockSyncOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("clock_sync", "Device time -> vehicle time: minimum-delay offset tracking with drift "
                                     "(common/clock_sync.h).");
    s.number("window_s", 2.0, 3600.0, "s", "sliding window for the fit", &O::window_s)
        .above("block_s", 0.0, 1800.0, "s", "one minimum per block (at most window_s / 2)", &O::block_s)
        .above("jump_threshold_us", 0.0, 1e12, "us", "error beyond which a sample's time is not trusted",
               &O::jump_threshold_us)
        .number("min_delay_us", 0.0, 1e12, "us", "known minimum transport delay", &O::min_delay_us)
        .number("settle_s", 0.0, 10.0, "s", "after a restart: the minimum must hold this long", &O::settle_s)
        .above("step_confirm_s", 0.0, 10.0, "s", "late beyond the threshold this long: an offset step",
               &O::step_confirm_s)
        .rule("block_s", [](const O& o) { return o.block_s <= o.window_s / 2; }, "must be at most window_s / 2");
    return s;
  }();
  return schema;
}

void ClockSyncOptions::Check() const { schema().check(*this); }

ClockSyncOptions ClockSyncOptions::from_config(const Config& section, const ClockSyncOptions& defaults) {
  ClockSyncOptions o = defaults;
  schema().read(section, &o);
  return o;
}

ClockSync::ClockSync(const ClockSyncOptions& options) : options_(options) {
  options_.Check();
  state_.late_bound_us = options_.jump_threshold_us;
}

double ClockSync::predict(int64_t device_us) const {
  return intercept_ + slope_ * static_cast<double>(device_us - reference_us_);
}

bool ClockSync::add(int64_t device_us, int64_t arrival_us) {
  const double offset = static_cast<double>(arrival_us - device_us);
  bool trusted = check_against_model(device_us, offset);
  ++state_.samples;
  last_device_us_ = device_us;
  add_to_blocks(device_us, offset);
  refit();
  if (state_.settling && !settled(device_us, offset)) trusted = false;
  if (!trusted) ++state_.untrusted;
  return trusted;
}

bool ClockSync::check_against_model(int64_t device_us, double offset) {
  if (!state_.valid) return true;  // nothing to check against (start, or just restarted)
  if (device_us <= last_device_us_) {
    restart("device time went backwards");
    return false;
  }
  const double excess = offset - predict(device_us);
  if (excess < -options_.jump_threshold_us) {
    restart("sample arrived " + std::to_string(static_cast<int64_t>(-excess)) +
            " us earlier than the clock model allows");
    return false;
  }
  if (excess <= state_.late_bound_us) {
    late_run_ = false;
    return true;
  }
  ++state_.late;
  if (!late_run_) {
    late_run_ = true;
    late_run_start_us_ = device_us;
  } else if (device_us - late_run_start_us_ >= static_cast<int64_t>(options_.step_confirm_s * 1e6)) {
    restart("clock offset stepped by " + std::to_string(static_cast<int64_t>(excess)) + " us");
  }
  return false;
}

void ClockSync::add_to_blocks(int64_t device_us, double offset) {
  const int64_t block_us = static_cast<int64_t>(options_.block_s * 1e6);
  if (have_current_ && device_us - current_.start_us >= block_us) {
    blocks_.push_back(current_);
    spreads_us_.push_back(current_.max_offset_us - current_.offset_us);
    const size_t max_spreads = static_cast<size_t>(std::max(1.0, options_.window_s / options_.block_s));
    while (spreads_us_.size() > max_spreads) spreads_us_.pop_front();
    update_late_bound();
    have_current_ = false;
  }
  if (!have_current_) {
    current_ = Block{device_us, offset, device_us, offset};
    have_current_ = true;
  } else {
    if (offset < current_.offset_us) {
      current_.offset_us = offset;
      current_.device_us = device_us;
    }
    current_.max_offset_us = std::max(current_.max_offset_us, offset);
  }
  const int64_t window_us = static_cast<int64_t>(options_.window_s * 1e6);
  while (!blocks_.empty() && device_us - blocks_.front().device_us > window_us) blocks_.pop_front();
}

void ClockSync::update_late_bound() {
  std::vector<double> spreads(spreads_us_.begin(), spreads_us_.end());
  // The lower median: a link that shows a spread in only half its blocks is
  // not yet known to jitter that much.
  const auto middle = spreads.begin() + static_cast<std::ptrdiff_t>((spreads.size() - 1) / 2);
  std::nth_element(spreads.begin(), middle, spreads.end());
  state_.late_bound_us = std::max(options_.jump_threshold_us, kLateBoundMargin * *middle);
}

bool ClockSync::settled(int64_t device_us, double offset) {
  if (!settle_anchored_ || offset < settle_offset_us_ - options_.jump_threshold_us / 2) {
    settle_anchored_ = true;
    settle_offset_us_ = offset;
    settle_start_us_ = device_us;
  }
  if (device_us - settle_start_us_ < static_cast<int64_t>(options_.settle_s * 1e6)) return false;
  state_.settling = false;
  return true;
}

void ClockSync::refit() {
  // Points: closed blocks; the open block's running minimum only until two
  // blocks have closed (a young block's minimum sits high in the jitter).
  const bool use_current = have_current_ && blocks_.size() < 2;
  const size_t n = blocks_.size() + (use_current ? 1 : 0);
  if (n == 0) {
    state_.valid = false;
    return;
  }
  reference_us_ = use_current ? current_.device_us : blocks_.back().device_us;
  auto point = [&](size_t i) -> const Block& { return i < blocks_.size() ? blocks_[i] : current_; };
  if (n < 3) {
    double lowest = point(0).offset_us;
    for (size_t i = 1; i < n; ++i) lowest = std::min(lowest, point(i).offset_us);
    intercept_ = lowest;
    slope_ = 0.0;
  } else {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < n; ++i) {
      const double x = static_cast<double>(point(i).device_us - reference_us_);
      const double y = point(i).offset_us;
      sx += x; sy += y; sxx += x * x; sxy += x * y;
    }
    const double denom = n * sxx - sx * sx;
    slope_ = denom > 0 ? (n * sxy - sx * sy) / denom : 0.0;
    intercept_ = (sy - slope_ * sx) / n;
  }
  state_.valid = true;
  state_.blocks = static_cast<int>(n);
  state_.offset_us = intercept_ - options_.min_delay_us;
  state_.drift_ppm = slope_ * 1e6;
}

int64_t ClockSync::to_vehicle(int64_t device_us) const {
  return device_us + static_cast<int64_t>(std::llround(predict(device_us) - options_.min_delay_us));
}

void ClockSync::restart(const std::string& why) {
  if (!state_.valid) return;  // no estimate (yet, or since the last restart)
  blocks_.clear();
  have_current_ = false;
  state_.valid = false;
  state_.settling = true;
  settle_anchored_ = false;
  late_run_ = false;
  ++state_.jumps;
  state_.last_jump = why;
}

}  // namespace nadir
