#include "processes/ins_bridge/ins_bridge.h"

#include <cmath>
#include <limits>

#include "common/channels.h"
#include "common/geometry.h"
#include "common/gps_time.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"

namespace nadir::ins_bridge {

InsBridge::InsBridge(const BridgeOptions& options, Bus& bus)
    : options_(options),
      bus_(bus),
      alt_parser_(make_altimeter_parser(options.altimeter)),
      converter_(Eigen::Vector3d(deg_to_rad(options.ins.imu_to_body_rpy_deg.x()),
                                 deg_to_rad(options.ins.imu_to_body_rpy_deg.y()),
                                 deg_to_rad(options.ins.imu_to_body_rpy_deg.z()))),
      clock_(options.ins.clock_sync),
      ins_byte_time_us_(options.ins.serial.byte_time_us()),
      alt_byte_time_us_(options.altimeter.serial.byte_time_us()) {
  options_.Check();
}

void InsBridge::note_bytes(int64_t* since_good, bool* flagged, size_t size) {
  *since_good += static_cast<int64_t>(size);
  if (*since_good >= options_.baud_mismatch_bytes && !*flagged) {
    *flagged = true;
    ++baud_episodes_;
  }
}

void InsBridge::on_ins_bytes(const uint8_t* data, size_t size, int64_t arrival_us) {
  note_bytes(&ins_bytes_since_good_, &ins_suspect_flagged_, size);
  frames_.clear();
  ins_parser_.feed(data, size, arrival_us, ins_byte_time_us_, &frames_);
  for (const NovatelFrame& frame : frames_) handle_frame(frame);
}

void InsBridge::on_altimeter_bytes(const uint8_t* data, size_t size, int64_t arrival_us) {
  note_bytes(&alt_bytes_since_good_, &alt_suspect_flagged_, size);
  lines_.clear();
  alt_splitter_.feed(data, size, arrival_us, alt_byte_time_us_, &lines_);
  for (const SerialLine& line : lines_) handle_line(line);
}

void InsBridge::on_ins_reopened() {
  ins_parser_.reset();
  // It may be another receiver or a rebooted one, its clock anywhere: samples
  // are flagged until the new estimate has settled, never shifted by the old one.
  clock_.restart("INS device reopened");
}
void InsBridge::on_altimeter_reopened() { alt_splitter_.reset(); }

void InsBridge::handle_frame(const NovatelFrame& frame) {
  ins_bytes_since_good_ = 0;
  ins_suspect_flagged_ = false;
  if (frame.kind == NovatelFrame::Kind::kInsStdDev) {
    stddev_ = frame.stddev;
    stddev_gps_us_ = gps_time_us(frame.stddev.gps_week, frame.stddev.gps_seconds);
    have_stddev_ = true;
    return;
  }
  InsPva pva = frame.pva;
  if (pva.gps_week < static_cast<uint32_t>(options_.ins.min_plausible_week)) {
    // A receiver reporting the week modulo 1024: the host clock picks the epoch.
    pva.gps_week = unwrap_week_1024(pva.gps_week, pva.gps_seconds, unix_to_gps_us(frame.end_arrival_us));
    ++time_.week_unwrapped;
  }
  const int64_t gps_us = gps_time_us(pva.gps_week, pva.gps_seconds);
  int32_t flags = 0;
  if (have_last_) {
    if (gps_us == last_gps_us_) {
      ++time_.duplicates;
      return;
    }
    if (gps_us < last_gps_us_) {
      ++time_.time_backwards;
      flags |= ins_t::FLAG_TIME_JUMP;
    }
    if (pva.gps_week != last_week_) ++time_.week_changes;
  }
  have_last_ = true;
  last_gps_us_ = gps_us;
  last_week_ = pva.gps_week;

  const int leap = options_.ins.leap_seconds >= 0 ? options_.ins.leap_seconds : leap_seconds_at(gps_us);
  if (have_leap_ && leap != time_.leap_seconds) ++time_.leap_changes;
  have_leap_ = true;
  time_.leap_seconds = leap;

  // UTC device time against the arrival of the frame's first byte; a sample
  // whose time the estimate cannot vouch for (restart after a time step, leap
  // second, host clock step or reopen; settling; arrived too late) is flagged.
  const int64_t device_unix_us = gps_to_unix_us(gps_us, leap);
  if (!clock_.add(device_unix_us, frame.start_arrival_us)) flags |= ins_t::FLAG_TIME_JUMP;

  ins_t msg{};
  msg.utime = clock_.to_vehicle(device_unix_us);
  msg.device_utime = gps_us;
  msg.gps_week = static_cast<int32_t>(pva.gps_week);
  msg.gps_seconds = pva.gps_seconds;
  const ProjectAttitude att = converter_.attitude(pva);
  msg.roll = att.roll;
  msg.pitch = att.pitch;
  msg.yaw = att.yaw;
  msg.has_rates = false;  // INSPVA carries no body rates
  const Eigen::Vector3d v = SpanConverter::velocity_ned(pva);
  for (int i = 0; i < 3; ++i) msg.velocity_ned[i] = v[i];
  msg.latitude_deg = pva.latitude_deg;
  msg.longitude_deg = pva.longitude_deg;
  msg.height_m = pva.height_m;
  msg.ins_status = pva.status;
  const bool good = pva.status == kInsSolutionGood || pva.status == kInsSolutionFree;
  const bool aligned = good || pva.status == kInsHighVariance || pva.status == kInsAlignmentComplete;
  if (aligned) flags |= ins_t::FLAG_ALIGNED;
  if (good) flags |= ins_t::FLAG_SOLUTION_GOOD;
  msg.flags = flags;
  if (have_stddev_ &&
      std::llabs(gps_us - stddev_gps_us_) <= static_cast<int64_t>(options_.ins.stddev_max_age_s * 1e6)) {
    msg.has_stddev = true;
    msg.attitude_stddev[0] = deg_to_rad(stddev_.roll_deg);
    msg.attitude_stddev[1] = deg_to_rad(stddev_.pitch_deg);
    msg.attitude_stddev[2] = deg_to_rad(stddev_.azimuth_deg);
    msg.velocity_stddev[0] = stddev_.north_velocity;
    msg.velocity_stddev[1] = stddev_.east_velocity;
    msg.velocity_stddev[2] = stddev_.up_velocity;
    msg.position_stddev[0] = stddev_.latitude_m;
    msg.position_stddev[1] = stddev_.longitude_m;
    msg.position_stddev[2] = stddev_.height_m;
  }
  bus_.publish(channels::kIns, msg);
  ++ins_published_;
}

void InsBridge::handle_line(const SerialLine& line) {
  ++alt_.lines;
  const AltimeterReading reading = alt_parser_->parse(line.text);
  altimeter_t msg{};
  msg.utime = line.start_arrival_us - std::llround(options_.altimeter.latency_ms * 1000.0);
  for (int i = 0; i < 3; ++i) msg.beam_body[i] = options_.altimeter.beam_body[i];
  msg.signal_quality = reading.signal_quality;
  msg.range_m = reading.range_m;
  if (!reading.parsed) {
    ++alt_.parse_errors;
    alt_.last_error = "byte " + std::to_string(line.offset) + ": " + alt_parser_->name() + ": " + reading.error;
    if (!options_.altimeter.publish_parse_errors) return;
    msg.validity = altimeter_t::VALID_PARSE_ERROR;
    msg.range_m = std::numeric_limits<double>::quiet_NaN();
    msg.signal_quality = -1.0f;
  } else {
    alt_bytes_since_good_ = 0;
    alt_suspect_flagged_ = false;
    if (reading.no_return) {
      ++alt_.no_return;
      msg.validity = altimeter_t::VALID_NO_RETURN;
    } else if (reading.range_m < options_.altimeter.min_range_m || reading.range_m > options_.altimeter.max_range_m) {
      ++alt_.out_of_range;
      msg.validity = altimeter_t::VALID_OUT_OF_RANGE;
    } else if (reading.signal_quality >= 0 && reading.signal_quality < options_.altimeter.min_signal_quality) {
      ++alt_.low_signal;
      msg.validity = altimeter_t::VALID_LOW_SIGNAL;
    } else {
      ++alt_.ok;
      msg.validity = altimeter_t::VALID_OK;
    }
  }
  bus_.publish(channels::kAltimeter, msg);
  ++alt_published_;
}

int64_t InsBridge::altimeter_rejected() const {
  return alt_.parse_errors + alt_splitter_.overlong() + alt_splitter_.truncated();
}

int64_t InsBridge::rejected_sentences() const { return ins_parser_.counts().rejected() + altimeter_rejected(); }

void InsBridge::report(StatusReport* r) const {
  const NovatelParserCounts& n = ins_parser_.counts();
  const ClockSyncState& c = clock_.state();
  r->received += n.frames + (alt_.lines - alt_.parse_errors) + rejected_sentences();
  r->published += ins_published_ + alt_published_;
  r->dropped += time_.duplicates;
  auto add = [&](const char* name, double value) { r->counters.emplace_back(name, value); };
  add("ins_bytes", static_cast<double>(n.bytes));
  add("ins_published", static_cast<double>(ins_published_));
  // Per sentence: accepted + rejected_* = every sentence the INS sent.
  add("ins_sentences_accepted", static_cast<double>(n.frames));
  add("ins_sentences_rejected", static_cast<double>(n.rejected()));
  add("ins_rejected_crc", static_cast<double>(n.crc_failures));
  add("ins_rejected_length", static_cast<double>(n.bad_length));
  add("ins_rejected_fields", static_cast<double>(n.field_errors));
  add("ins_rejected_unknown_log", static_cast<double>(n.unknown_messages));
  add("ins_rejected_truncated", static_cast<double>(n.truncated));
  add("ins_garbage_bytes", static_cast<double>(n.garbage_bytes));
  add("ins_duplicates", static_cast<double>(time_.duplicates));
  add("ins_time_backwards", static_cast<double>(time_.time_backwards));
  add("gps_week_changes", static_cast<double>(time_.week_changes));
  add("gps_week_unwrapped", static_cast<double>(time_.week_unwrapped));
  add("gps_leap_seconds", time_.leap_seconds);
  add("gps_leap_changes", static_cast<double>(time_.leap_changes));
  add("clock_valid", c.valid ? 1.0 : 0.0);
  add("clock_offset_us", c.offset_us);
  add("clock_drift_ppm", c.drift_ppm);
  add("clock_blocks", c.blocks);
  add("clock_samples", static_cast<double>(c.samples));
  add("clock_jumps", static_cast<double>(c.jumps));
  add("clock_settling", c.settling ? 1.0 : 0.0);
  add("clock_late_samples", static_cast<double>(c.late));
  add("clock_late_bound_us", c.late_bound_us);
  add("clock_flagged_samples", static_cast<double>(c.untrusted));
  add("alt_bytes", static_cast<double>(alt_splitter_.bytes()));
  // Per line: accepted (published with a validity) + rejected_* = every line.
  add("alt_lines_accepted", static_cast<double>(alt_.lines - alt_.parse_errors));
  add("alt_lines_rejected", static_cast<double>(altimeter_rejected()));
  add("alt_rejected_parse", static_cast<double>(alt_.parse_errors));
  add("alt_rejected_overlong", static_cast<double>(alt_splitter_.overlong()));
  add("alt_rejected_truncated", static_cast<double>(alt_splitter_.truncated()));
  add("alt_ok", static_cast<double>(alt_.ok));
  add("alt_no_return", static_cast<double>(alt_.no_return));
  add("alt_out_of_range", static_cast<double>(alt_.out_of_range));
  add("alt_low_signal", static_cast<double>(alt_.low_signal));
  add("baud_mismatch_suspected", static_cast<double>(baud_episodes_));

  auto warn = [&](const std::string& why) {
    if (r->state == status_t::STATE_OK) r->state = status_t::STATE_WARN;
    if (!r->detail.empty()) r->detail += "; ";
    r->detail += why;
  };
  if (ins_baud_suspect()) warn("INS: bytes but no valid frame, baud mismatch? (" + n.last_error + ")");
  if (altimeter_baud_suspect()) warn("altimeter: bytes but no valid line, baud mismatch? (" + alt_.last_error + ")");
  if (c.jumps > 0 && !c.last_jump.empty() && !c.valid) warn("INS clock: " + c.last_jump);
}

}  // namespace nadir::ins_bridge
