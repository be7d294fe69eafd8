#include "processes/camera_capture/capture_options.h"

namespace nadir {

CaptureOptions CaptureOptions::FromConfig(const Config& c) {
  CaptureOptions o;
  c.require_known_keys({"camera", "trigger_input", "timing", "association", "clock_sync", "unassociated_frames",
                        "reconnect"});
  o.camera = CameraOptions::FromConfig(c.section_or_empty("camera"));
  const Config trigger = c.section_or_empty("trigger_input");
  trigger.require_known_keys({"source", "chip", "line", "edge"});
  o.trigger_input = trigger.get<std::string>("source", o.trigger_input);
  if (o.trigger_input != "gpiod" && o.trigger_input != "none" && o.trigger_input != "scripted") {
    throw trigger.error("source", "= '" + o.trigger_input + "' is not gpiod, none or scripted");
  }
  o.gpiod.chip = trigger.get<std::string>("chip", o.gpiod.chip);
  o.gpiod.line = trigger.get_in_range<int>("line", o.gpiod.line, 0, 4095);
  o.gpiod.edge = trigger.get<std::string>("edge", o.gpiod.edge);
  if (o.gpiod.edge != "rising" && o.gpiod.edge != "falling" && o.gpiod.edge != "both") {
    throw trigger.error("edge", "= '" + o.gpiod.edge + "' is not rising, falling or both");
  }
  o.timing = ImageTimingOptions::FromConfig(c.section_or_empty("timing"));
  o.association = AssociationOptions::FromConfig(c.section_or_empty("association"));
  o.clock_sync = ClockSyncOptions::from_config(c.section_or_empty("clock_sync"), o.clock_sync);
  const std::string policy = c.get<std::string>("unassociated_frames", "publish_flagged");
  if (policy != "publish_flagged" && policy != "drop") {
    throw c.error("unassociated_frames", "= '" + policy + "' is not publish_flagged or drop");
  }
  o.publish_unassociated = policy == "publish_flagged";
  const Config reconnect = c.section_or_empty("reconnect");
  reconnect.require_known_keys({"initial_backoff_s", "max_backoff_s", "frame_timeout_s", "retry_at_start"});
  o.reconnect_initial_backoff_s =
      reconnect.get_in_range<double>("initial_backoff_s", o.reconnect_initial_backoff_s, 0.01, 60.0);
  o.reconnect_max_backoff_s = reconnect.get_in_range<double>("max_backoff_s", o.reconnect_max_backoff_s,
                                                             o.reconnect_initial_backoff_s, 600.0);
  o.frame_timeout_s = reconnect.get_in_range<double>("frame_timeout_s", o.frame_timeout_s, 0.1, 600.0);
  o.retry_at_start = reconnect.get<bool>("retry_at_start", o.retry_at_start);
  o.Check();
  return o;
}

void CaptureOptions::Check() const {
  camera.Check();
  association.Check();
  clock_sync.Check();
  const std::string s = "camera_capture";
  require_option(trigger_input == "gpiod" || trigger_input == "none" || trigger_input == "scripted", s,
                 "trigger_input.source", "must be gpiod, none or scripted");
  require_option(reconnect_initial_backoff_s > 0 && reconnect_max_backoff_s >= reconnect_initial_backoff_s, s,
                 "reconnect.max_backoff_s", "must be >= reconnect.initial_backoff_s > 0");
  require_option(frame_timeout_s > 0, s, "reconnect.frame_timeout_s", "must be > 0");
}

}  // namespace nadir
