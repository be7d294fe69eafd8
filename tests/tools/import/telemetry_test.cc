// SRT and CSV telemetry: good input read field by field; every malformed
// block / line named by file and line, or skipped and counted.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "tools/import/telemetry.h"

namespace nadir::import {
namespace {

const char* kSrt =
    "1\n"
    "00:00:00,000 --> 00:00:00,033\n"
    "<font size=\"28\">FrameCnt: 1, DiffTime: 33ms\n"
    "2024-05-01 10:00:00.000\n"
    "[iso: 100] [latitude: 47.500000] [longitude: 8.250000] [rel_alt: 40.000 abs_alt: 480.500] "
    "[gb_yaw: 90.0 gb_pitch: -90.0 gb_roll: 0.0] [flight_yaw: 91.0 flight_pitch: -2.0 flight_roll: 1.5]</font>\n"
    "\n"
    "2\n"
    "00:00:00,033 --> 00:00:00,066\n"
    "FrameCnt: 2, DiffTime: 33ms\n"
    "2024-05-01 10:00:00.033\n"
    "[latitude: 47.500010] [longitude: 8.250000] [rel_alt: 40.100 abs_alt: 480.600] "
    "[gb_yaw: -179.5 gb_pitch: -89.0 gb_roll: 0.5] [range: 39.8]\n";

TEST(SrtTelemetry, ReadsEveryField) {
  const Telemetry t = parse_srt_text(kSrt, "flight.SRT", false);
  ASSERT_EQ(t.records.size(), 2u);
  const TelemetryRecord& a = t.records[0];
  EXPECT_EQ(a.line, 1);
  EXPECT_EQ(a.frame, 1);
  EXPECT_DOUBLE_EQ(a.time_s, 0.0);
  EXPECT_DOUBLE_EQ(a.lat_deg, 47.5);
  EXPECT_DOUBLE_EQ(a.lon_deg, 8.25);
  EXPECT_DOUBLE_EQ(a.height_m, 40.0);
  EXPECT_TRUE(a.has_alt);
  EXPECT_DOUBLE_EQ(a.alt_m, 480.5);
  EXPECT_TRUE(a.has_gimbal);
  EXPECT_DOUBLE_EQ(a.gimbal_yaw_deg, 90.0);
  EXPECT_DOUBLE_EQ(a.gimbal_pitch_deg, -90.0);
  EXPECT_TRUE(a.has_body);
  EXPECT_DOUBLE_EQ(a.yaw_deg, 91.0);
  EXPECT_DOUBLE_EQ(a.roll_deg, 1.5);
  EXPECT_FALSE(a.has_range);
  EXPECT_NEAR(a.absolute_time_s, 1714557600.0, 1e-6);  // 2024-05-01 10:00:00 UTC
  const TelemetryRecord& b = t.records[1];
  EXPECT_EQ(b.line, 7);
  EXPECT_NEAR(b.time_s, 0.033, 1e-12);
  EXPECT_NEAR(b.absolute_time_s - a.absolute_time_s, 0.033, 1e-6);
  EXPECT_FALSE(b.has_body);
  EXPECT_TRUE(b.has_range);
  EXPECT_DOUBLE_EQ(b.range_m, 39.8);
  EXPECT_DOUBLE_EQ(b.gimbal_yaw_deg, -179.5);
}

std::string error_of(const std::string& text, bool srt) {
  try {
    if (srt) {
      parse_srt_text(text, "f.SRT", false);
    } else {
      parse_csv_text(text, "f.csv", false);
    }
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(SrtTelemetry, BadTimeLineNamesFileAndLine) {
  std::string text = kSrt;
  text.replace(text.find("00:00:00,033 --> 00:00:00,066"), 29, "00:00:00.033 -> 00:00:00,066");
  EXPECT_EQ(error_of(text, true).rfind("f.SRT:8: time line", 0), 0u) << error_of(text, true);
}

TEST(SrtTelemetry, MissingFieldNamesFileAndLine) {
  std::string text = kSrt;
  text.replace(text.find("[gb_yaw: -179.5 "), 16, "");
  const std::string e = error_of(text, true);
  EXPECT_EQ(e, "f.SRT:7: subtitle block (lines 7-11): field 'gb_yaw' is missing");
}

TEST(SrtTelemetry, BadIndexAndNumber) {
  std::string text = kSrt;
  text.replace(text.find("2\n00:00:00,033"), 1, "x");
  EXPECT_EQ(error_of(text, true).rfind("f.SRT:7: subtitle index", 0), 0u) << error_of(text, true);
  text = kSrt;
  text.replace(text.find("47.500010"), 9, "47.5.0010");
  EXPECT_EQ(error_of(text, true), "f.SRT:11: field 'latitude' is not a number: '47.5.0010'");
}

TEST(SrtTelemetry, SkipBadCountsTheBlock) {
  std::string text = kSrt;
  text.replace(text.find("[latitude: 47.500010] "), 22, "");
  const Telemetry t = parse_srt_text(text, "f.SRT", true);
  ASSERT_EQ(t.records.size(), 1u);
  ASSERT_EQ(t.skipped.size(), 1u);
  EXPECT_EQ(t.skipped[0].where, "f.SRT:7");
  EXPECT_NE(t.skipped[0].reason.find("latitude"), std::string::npos);
}

const char* kCsv =
    "# exported by a test\n"
    "time_s,roll_deg,pitch_deg,yaw_deg,height_m,lat_deg,lon_deg,alt_m\n"
    "0.0,1.0,-2.0,180.0,40.0,47.5,8.25,480.0\n"
    "0.5,1.5,-2.5,-179.0,40.5,47.50001,8.25,480.5\n";

TEST(CsvTelemetry, ReadsColumnsByName) {
  const Telemetry t = parse_csv_text(kCsv, "f.csv", false);
  ASSERT_EQ(t.records.size(), 2u);
  EXPECT_EQ(t.records[1].line, 4);
  EXPECT_DOUBLE_EQ(t.records[1].time_s, 0.5);
  EXPECT_DOUBLE_EQ(t.records[1].yaw_deg, -179.0);
  EXPECT_DOUBLE_EQ(t.records[1].pitch_deg, -2.5);
  EXPECT_TRUE(t.records[1].has_height);
  EXPECT_FALSE(t.records[1].has_range);
  EXPECT_DOUBLE_EQ(t.records[1].height_m, 40.5);
  // columns in another order, with a range
  const Telemetry r = parse_csv_text("lat_deg,lon_deg,alt_m,time_s,range_m,yaw_deg,pitch_deg,roll_deg\n"
                                     "47.5,8.25,480,2.0,39.5,10,0,0\n", "g.csv", false);
  ASSERT_EQ(r.records.size(), 1u);
  EXPECT_TRUE(r.records[0].has_range);
  EXPECT_DOUBLE_EQ(r.records[0].range_m, 39.5);
  EXPECT_DOUBLE_EQ(r.records[0].yaw_deg, 10.0);
  EXPECT_DOUBLE_EQ(r.records[0].time_s, 2.0);
}

TEST(CsvTelemetry, MissingColumnNamesHeaderLine) {
  const std::string e = error_of("time_s,roll_deg,pitch_deg,height_m,lat_deg,lon_deg,alt_m\n0,0,0,40,47,8,400\n", false);
  EXPECT_EQ(e.rfind("f.csv:1: header misses column 'yaw_deg'", 0), 0u) << e;
  const std::string h = error_of("time_s,roll_deg,pitch_deg,yaw_deg,lat_deg,lon_deg,alt_m\n0,0,0,0,47,8,400\n", false);
  EXPECT_NE(h.find("f.csv:1: header needs a range_m or a height_m"), std::string::npos) << h;
}

TEST(CsvTelemetry, BadLinesNamedOrSkipped) {
  std::string text = std::string(kCsv) + "1.0,abc,0,0,40,47.5,8.25,480\n1.5,0,0,0,40,47.5\n";
  EXPECT_EQ(error_of(text, false), "f.csv:5: column 'roll_deg' is not a number: 'abc'");
  const Telemetry t = parse_csv_text(text, "f.csv", true);
  EXPECT_EQ(t.records.size(), 2u);
  ASSERT_EQ(t.skipped.size(), 2u);
  EXPECT_EQ(t.skipped[0].where, "f.csv:5");
  EXPECT_EQ(t.skipped[1].where, "f.csv:6");
  EXPECT_EQ(t.skipped[1].reason, "6 columns where the header has 8");
}

TEST(DateTime, ExifAndIsoForms) {
  double s = 0;
  ASSERT_TRUE(parse_date_time("2013:06:04 13:37:29", &s));
  EXPECT_DOUBLE_EQ(s, 1370353049.0);
  ASSERT_TRUE(parse_date_time("2013-06-04T17:38:03", &s));
  EXPECT_DOUBLE_EQ(s, 1370367483.0);
  ASSERT_TRUE(parse_date_time("2013-06-04 17:38:03.250", &s));
  EXPECT_DOUBLE_EQ(s, 1370367483.25);
  EXPECT_FALSE(parse_date_time("2013-13-04 17:38:03", &s));
  EXPECT_FALSE(parse_date_time("yesterday", &s));
}

}  // namespace
}  // namespace nadir::import
