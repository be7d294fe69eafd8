// Every file under config/ loads, and a misspelt key is an error naming the
// file, the full key path and the nearest known key in every place a user
// writes configuration: config/*.yaml and overlays, --set, flight profiles,
// sim sensor sets, installation files, camera files (campaign specs:
// tests/integration/campaign_check_test.sh). The checked-in configuration
// reference is the one the schemas generate.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "processes/mavlink_bridge/bridge_options.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/sensor_options.h"
#include "processes/vo_solver/vo_solver_options.h"
#include "tools/config/config_catalog.h"
#include "tools/import/flight_import.h"

namespace nadir {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = NADIR_SOURCE_DIR;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> files_in(const std::string& folder) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(kRoot + "/" + folder)) {
    if (e.path().extension() == ".yaml") out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The text with `line` inserted after the first line that starts with `after`.
std::string with_line(const std::string& text, const std::string& after, const std::string& line) {
  const size_t at = text.find("\n" + after);
  EXPECT_NE(at, std::string::npos) << after;
  const size_t end = text.find('\n', at + 1);
  return text.substr(0, end + 1) + line + "\n" + text.substr(end + 1);
}

std::string temp_file(const std::string& name, const std::string& text) {
  const std::string path = (fs::temp_directory_path() / ("nadir_config_test_" + name)).string();
  std::ofstream(path) << text;
  return path;
}

// The message of the error `f` throws (ConfigError or runtime_error).
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(ConfigSources, EveryFileUnderConfigLoads) {
  const Config root = Config::load_file(kRoot + "/config/default.yaml");
  EXPECT_NO_THROW(check_every_section(root));
  for (const std::string& path : files_in("config/installation")) {
    Config c = Config::load_file(kRoot + "/config/default.yaml");
    c.apply_overlay(Config::load_file(path));
    EXPECT_NO_THROW(check_every_section(c)) << path;
  }
  // The simulator's 12 MP camera (nadir_sim --config-overlay).
  Config camera_12mp = Config::load_file(kRoot + "/config/default.yaml");
  camera_12mp.apply_overlay(Config::load_file(kRoot + "/config/sim_camera_12mp.yaml"));
  EXPECT_NO_THROW(check_every_section(camera_12mp));
  EXPECT_EQ(camera_12mp.section("camera").get<int>("width"), 3000);
  for (const std::string& path : files_in("config/profiles")) {
    EXPECT_NO_THROW(sim::FlightProfile::load(path)) << path;
  }
  const Config sensors = Config::load_file(kRoot + "/config/sim_sensors.yaml");
  int sets = 0;
  for (const auto& item : sensors.node()) {
    EXPECT_NO_THROW(sim::SensorOptions::from_config(sensors, item.first.as<std::string>())) << item.first;
    ++sets;
  }
  EXPECT_GE(sets, 5);
  for (const std::string& path : files_in("config/cameras")) {
    EXPECT_NO_THROW(import::read_camera_file(path)) << path;
  }
}

TEST(ConfigSources, MisspeltKeyInTheSharedFile) {
  const std::string text = read_text(kRoot + "/config/default.yaml");
  struct Case {
    std::string after, line, key, suggestion;
  };
  const Case cases[] = {
      {"vo_solver:", "  min_featurs: 12", "vo_solver.min_featurs", "vo_solver.min_features"},
      {"tracker:", "  klt_windw_px: 21", "tracker.klt_windw_px", "tracker.klt_window_px"},
      {"yaw_fusion:", "  ins_yaw_gate_sigmas: 3", "yaw_fusion.ins_yaw_gate_sigmas", "yaw_fusion.ins_yaw_gate_sigma"},
      {"input_checks:", "  max_ahead: 1", "input_checks.max_ahead", "input_checks.max_ahead_s"},
      {"camera:", "  rate_hzz: 14", "camera.rate_hzz", "camera.rate_hz"},
      {"altimeter:", "  beam_bodi: [0, 0, 1]", "altimeter.beam_bodi", "altimeter.beam_body"},
      {"camera_capture:", "  unassociated_frame: drop", "camera_capture.unassociated_frame",
       "camera_capture.unassociated_frames"},
      {"ins_bridge:", "  baud_mismatch_byte: 2048", "ins_bridge.baud_mismatch_byte", "ins_bridge.baud_mismatch_bytes"},
      {"mavlink_bridge:", "  system_idd: 1", "mavlink_bridge.system_idd", "mavlink_bridge.system_id"},
  };
  for (const Case& c : cases) {
    const std::string path = temp_file("shared.yaml", with_line(text, c.after, c.line));
    const std::string e = error_of([&] { check_every_section(Config::load_file(path)); });
    EXPECT_HAS(e, path + ": key '" + c.key + "' is not a known key (line ");
    EXPECT_HAS(e, "did you mean " + c.suggestion + "?");
  }
  // A section no reader knows (a misspelt section name) is refused by the check.
  const std::string e = error_of([&] {
    check_every_section(Config::load_file(temp_file("sections.yaml", text + "\nvo_slover: {variant: paper}\n")));
  });
  EXPECT_HAS(e, "did you mean vo_solver?");
}

TEST(ConfigSources, MisspeltKeyInSetAndOverlay) {
  Config c = Config::load_file(kRoot + "/config/default.yaml");
  c.apply_override("vo_solver.min_featurs=3");
  std::string e = error_of([&] { VoSolverOptions::from_config(c); });
  EXPECT_HAS(e, "(with vo_solver.min_featurs=3): key 'vo_solver.min_featurs' is not a known key");
  EXPECT_HAS(e, "did you mean vo_solver.min_features?");
  c = Config::load_file(kRoot + "/config/default.yaml");
  c.apply_override("vo_solver.feature_depth.anchor_radus=0.3");
  e = error_of([&] { VoSolverOptions::from_config(c); });
  EXPECT_HAS(e, "did you mean vo_solver.feature_depth.anchor_radius?");
  // An overlay (an installation file, a calibration) is applied as --set per leaf.
  c = Config::load_file(kRoot + "/config/default.yaml");
  c.apply_overlay(Config::parse("camera: {lever_arm: [1, 0, 0]}\n", "install.yaml"));
  e = error_of([&] { check_every_section(c); });
  EXPECT_HAS(e, "key 'camera.lever_arm' is not a known key");
  EXPECT_HAS(e, "did you mean camera.lever_arm_m?");
  // The same for the MAVLink bridge's settings.
  c = Config::load_file(kRoot + "/config/default.yaml");
  c.apply_override("mavlink_bridge.input.distance_sensr=false");
  e = error_of([&] { mavlink_bridge::BridgeOptions::from_config(c); });
  EXPECT_HAS(e, "did you mean mavlink_bridge.input.distance_sensor?");
}

TEST(ConfigSources, MisspeltKeyInAnInstallationFile) {
  const std::string path = files_in("config/installation").front();
  const std::string bad =
      temp_file("installation.yaml", with_line(read_text(path), "altimeter:", "  range_bias: 0.15"));
  Config c = Config::load_file(kRoot + "/config/default.yaml");
  c.apply_overlay(Config::load_file(bad));
  const std::string e = error_of([&] { check_every_section(c); });
  EXPECT_HAS(e, "key 'altimeter.range_bias' is not a known key");
  EXPECT_HAS(e, "did you mean altimeter.range_bias_m?");
}

TEST(ConfigSources, MisspeltKeyInAFlightProfile) {
  const std::string text = read_text(kRoot + "/config/profiles/test1.yaml");
  std::string e = error_of([&] { sim::FlightProfile::parse(text + "sped_mps: 30\n", "test1.yaml"); });
  EXPECT_HAS(e, "test1.yaml: key 'sped_mps' is not a known key (line ");
  EXPECT_HAS(e, "did you mean speed_mps?");
  e = error_of([&] {
    sim::FlightProfile::parse(with_line(text, "name:", "oscillation: {roll_deg: 0.8, pich_deg: 0.6}"), "t.yaml");
  });
  EXPECT_HAS(e, "did you mean oscillation.pitch_deg?");
  std::string legs = text;
  legs.replace(legs.find("bank_deg: 12"), 12, "bank_dg: 12");
  e = error_of([&] { sim::FlightProfile::parse(legs, "t.yaml"); });
  EXPECT_HAS(e, "key 'legs[1].bank_dg' is not a known key");
  EXPECT_HAS(e, "did you mean legs[1].bank_deg?");
}

TEST(ConfigSources, MisspeltKeyInASimSensorSet) {
  const std::string text = read_text(kRoot + "/config/sim_sensors.yaml");
  const Config sensors = Config::parse(text + "\ntypo_set:\n  ins: {rate_hz: 100, roll_pitch_nois_deg: 0.1}\n",
                                       "sim_sensors.yaml");
  const std::string e = error_of([&] { sim::SensorOptions::from_config(sensors, "typo_set"); });
  EXPECT_HAS(e, "sim_sensors.yaml: key 'typo_set.ins.roll_pitch_nois_deg' is not a known key (line ");
  EXPECT_HAS(e, "did you mean typo_set.ins.roll_pitch_noise_deg?");
}

TEST(ConfigSources, MisspeltKeyInACameraFile) {
  const std::string path = files_in("config/cameras").front();
  std::string text = read_text(path);
  text.replace(text.find("\nmount_rpy_deg:"), 15, "\nmount_rpy_dg:");
  const std::string bad = temp_file("camera.yaml", text);
  const std::string e = error_of([&] { import::read_camera_file(bad); });
  EXPECT_HAS(e, bad + ": key 'mount_rpy_dg' is not a known key; did you mean mount_rpy_deg?");
}

TEST(ConfigSources, CheckedInReferenceIsWhatTheSchemasGenerate) {
  EXPECT_TRUE(read_text(kRoot + "/docs/reference/configuration.md") == configuration_reference())
      << "regenerate: build/bin/nadir_config --config-reference --out docs/reference/configuration.md";
}

}  // namespace
}  // namespace nadir
