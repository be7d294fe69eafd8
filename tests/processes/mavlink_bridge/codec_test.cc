// The codec's message table against the MAVLink definitions: CRC_EXTRA
// recomputed from each field list equals the published value, payload lengths
// equal the definitions', and payloads and frames round-trip (v2 with
// truncated zeros, v1 without extensions).

#include <gtest/gtest.h>

#include <cmath>

#include "processes/mavlink_bridge/mavlink_codec.h"
#include "processes/mavlink_bridge/mavlink_crc.h"
#include "processes/mavlink_bridge/mavlink_frame.h"

namespace nadir::mavlink {
namespace {

TEST(MavlinkCrc, MatchesTheReferenceCheckValue) {
  // CRC-16/MCRF4XX of "123456789" is 0x6F91 (the catalogued check value).
  EXPECT_EQ(crc_accumulate(std::string("123456789"), kCrcSeed), 0x6F91);
}

TEST(MavlinkCodec, CrcExtraRecomputedFromTheFieldListsMatchesTheDefinitions) {
  int checked = 0;
  for_each_message_type([&](auto m) {
    using M = decltype(m);
    EXPECT_EQ(crc_extra_of<M>(), M::kCrcExtra) << M::kName;
    ++checked;
  });
  EXPECT_EQ(checked, 11);
}

TEST(MavlinkCodec, PayloadLengthsMatchTheDefinitions) {
  // {id, base length (MAVLink 1), full length} from common.xml / minimal.xml.
  const int expected[][3] = {{0, 9, 9},     {2, 12, 12},   {24, 30, 52},   {30, 28, 28},
                             {31, 32, 48},  {33, 28, 28},  {102, 32, 117}, {111, 16, 18},
                             {132, 14, 39}, {232, 63, 65}, {331, 230, 233}};
  for (const auto& e : expected) {
    const MessageInfo* info = find_message(static_cast<uint32_t>(e[0]));
    ASSERT_NE(info, nullptr) << e[0];
    EXPECT_EQ(info->base_length, e[1]) << info->name;
    EXPECT_EQ(info->length, e[2]) << info->name;
  }
  EXPECT_EQ(find_message(105), nullptr);  // HIGHRES_IMU: not read
}

TEST(MavlinkCodec, PayloadRoundTripsAndIsLittleEndian) {
  Attitude a;
  a.time_boot_ms = 0x01020304;
  a.roll = 0.25f;
  a.yawspeed = -1.5f;
  const std::vector<uint8_t> payload = encode_payload(a);
  ASSERT_EQ(payload.size(), 28u);
  EXPECT_EQ(payload[0], 0x04);
  EXPECT_EQ(payload[3], 0x01);
  const Attitude b = decode_payload<Attitude>(payload.data(), payload.size());
  EXPECT_EQ(b.time_boot_ms, a.time_boot_ms);
  EXPECT_EQ(b.roll, a.roll);
  EXPECT_EQ(b.yawspeed, a.yawspeed);
}

TEST(MavlinkFrame, V2TruncatesTrailingZerosAndTheParserRestoresThem) {
  FrameEncoder encoder(7, 197);
  TimeSync t;
  t.tc1 = 0;
  t.ts1 = 5;  // everything after the first byte of ts1 is zero
  const std::vector<uint8_t> bytes = encoder.encode(t);
  ASSERT_EQ(bytes.size(), 10u + 9u + 2u);
  EXPECT_EQ(bytes[1], 9);  // payload length after truncation
  FrameParser parser;
  std::vector<Frame> frames;
  parser.feed(bytes.data(), bytes.size(), 1000, 0.0, &frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].sysid, 7);
  EXPECT_EQ(frames[0].compid, 197);
  EXPECT_EQ(frames[0].decode<TimeSync>().ts1, 5);
  EXPECT_EQ(frames[0].start_arrival_us, 1000);

  Heartbeat zero;  // all-zero payload but mavlink_version: one byte kept at least
  zero.mavlink_version = 0;
  EXPECT_EQ(encoder.encode(zero)[1], 1);
}

TEST(MavlinkFrame, V1IsAcceptedWithBaseFieldsOnly) {
  FrameEncoder encoder(1, 1);
  DistanceSensor d;
  d.time_boot_ms = 1234;
  d.current_distance = 15000;
  d.orientation = kSensorRotationDown;
  d.signal_quality = 90;  // an extension: not in a v1 frame
  const std::vector<uint8_t> bytes = encoder.encode(d, 1);
  EXPECT_EQ(bytes[0], kStxV1);
  EXPECT_EQ(bytes.size(), 6u + 14u + 2u);
  FrameParser parser;
  std::vector<Frame> frames;
  parser.feed(bytes.data(), bytes.size(), 0, 0.0, &frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].version, 1);
  const DistanceSensor got = frames[0].decode<DistanceSensor>();
  EXPECT_EQ(got.current_distance, 15000);
  EXPECT_EQ(got.signal_quality, 0);

  FrameParserOptions v2_only;
  v2_only.accept_v1 = false;
  FrameParser strict(v2_only);
  frames.clear();
  strict.feed(bytes.data(), bytes.size(), 0, 0.0, &frames);
  strict.end_of_datagram(&frames);
  EXPECT_TRUE(frames.empty());
  EXPECT_EQ(strict.counts().rejected_spans, 1);
}

TEST(MavlinkFrame, SignedFramesAreAcceptedWithTheSignatureSkipped) {
  FrameEncoder encoder(1, 1);
  std::vector<uint8_t> bytes = encoder.encode(Attitude{});
  // Mark it signed: the CRC covers the flags, so recompute it, then append 13 bytes.
  bytes[2] = kIncompatSigned;
  bytes.resize(bytes.size() - 2);
  uint16_t crc = crc_accumulate(bytes.data() + 1, bytes.size() - 1, kCrcSeed);
  crc = crc_accumulate(Attitude::kCrcExtra, crc);
  bytes.push_back(static_cast<uint8_t>(crc));
  bytes.push_back(static_cast<uint8_t>(crc >> 8));
  bytes.insert(bytes.end(), kSignatureLength, 0xAB);
  bytes.insert(bytes.end(), {0xFD});  // and the start of the next frame in the stream
  FrameParser parser;
  std::vector<Frame> frames;
  parser.feed(bytes.data(), bytes.size(), 0, 0.0, &frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_TRUE(frames[0].is_signed);
  EXPECT_EQ(parser.counts().frames_signed, 1);
}

TEST(MavlinkFrame, UnknownMessagesAreSkippedWholeWhenAFrameFollows) {
  FrameEncoder encoder(1, 1);
  std::vector<uint8_t> payload(20, 0x5A);
  std::vector<uint8_t> stream = encoder.encode_raw(105, 93, payload, 20, 2);  // HIGHRES_IMU-like
  const std::vector<uint8_t> attitude = encoder.encode(Attitude{});
  stream.insert(stream.end(), attitude.begin(), attitude.end());
  FrameParser parser;
  std::vector<Frame> frames;
  parser.feed(stream.data(), stream.size(), 0, 0.0, &frames);
  parser.end_of_datagram(&frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].msgid, Attitude::kId);
  EXPECT_EQ(parser.counts().unknown_skipped, 1);
  EXPECT_EQ(parser.counts().rejected_spans, 0);
  EXPECT_EQ(parser.counts().garbage_bytes, 0);
}

TEST(MavlinkFrame, AReopenedLinkDropsAnUnfinishedFrameAsOneRejectedSpan) {
  FrameEncoder encoder(1, 1);
  const std::vector<uint8_t> frame = encoder.encode(Attitude{});
  FrameParser parser;
  std::vector<Frame> frames;
  parser.feed(frame.data(), 12, 0, 0.0, &frames);  // unplugged mid-frame
  parser.reset();
  parser.feed(frame.data(), frame.size(), 0, 0.0, &frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(parser.counts().truncated, 1);
  EXPECT_EQ(parser.counts().rejected_spans, 1);
  EXPECT_EQ(parser.counts().garbage_bytes, 12);
}

TEST(MavlinkFrame, ByteTimesFollowTheLine) {
  FrameEncoder encoder(1, 1);
  std::vector<uint8_t> stream = {0x00, 0x11};
  const std::vector<uint8_t> frame = encoder.encode(SystemTime{});
  stream.insert(stream.end(), frame.begin(), frame.end());
  FrameParser parser;
  std::vector<Frame> frames;
  parser.feed(stream.data(), stream.size(), 10000, 100.0, &frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].start_arrival_us, 10200);  // two garbage bytes before it
  EXPECT_EQ(parser.counts().garbage_bytes, 2);
  EXPECT_EQ(parser.counts().rejected_spans, 1);
}

}  // namespace
}  // namespace nadir::mavlink
