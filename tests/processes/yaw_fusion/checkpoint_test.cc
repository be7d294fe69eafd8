// Yaw fusion's checkpoint file: what is saved loads back bit for bit, a file
// from before the heading bias was kept (a bare POSE) still loads without it,
// and a damaged or unwritable file is named, never a crash.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/message_guard.h"
#include "processes/yaw_fusion/checkpoint.h"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

pose_t a_pose() {
  pose_t pose{};
  pose.utime = 1767225600123456;
  pose.position_ned[0] = 1234.5;
  pose.position_ned[1] = -678.25;
  pose.position_ned[2] = -301.0;
  pose.velocity_ned[0] = 29.5;
  pose.yaw = 1.25;
  pose.yaw_variance = 3e-6;
  pose.position_covariance[0][0] = pose.position_covariance[1][1] = 4.0;
  pose.position_covariance[0][1] = pose.position_covariance[1][0] = 0.5;
  pose.position_covariance[2][2] = 1.0;
  pose.frames = 4200;
  return pose;
}

TEST(PoseCheckpoint, KeepsThePoseAndTheHeadingBias) {
  testing::TempDir dir("checkpoint");
  PoseCheckpoint checkpoint(dir.file("yaw_fusion.checkpoint"));
  std::string problem;
  EXPECT_FALSE(checkpoint.load(&problem).has_value());  // none yet: a fresh start, no problem
  EXPECT_EQ(problem, "");

  yaw_fusion_checkpoint_t saved = checkpoint_without_bias(a_pose());
  saved.has_heading_bias = true;
  saved.heading_bias_rad[0] = 0.0015;
  saved.heading_bias_rad[1] = -0.0002;
  saved.heading_bias_covariance[0][0] = 1e-8;
  saved.heading_bias_covariance[1][1] = 2e-8;
  saved.heading_bias_covariance[0][1] = saved.heading_bias_covariance[1][0] = -3e-9;
  saved.heading_bias_estimated = true;
  saved.heading_bias_prior_covariance[0][0] = saved.heading_bias_prior_covariance[1][1] = 3e-6;
  checkpoint.save(saved);
  EXPECT_EQ(checkpoint.saves(), 1);

  const auto loaded = checkpoint.load(&problem);
  ASSERT_TRUE(loaded.has_value()) << problem;
  EXPECT_EQ(encode_message(*loaded), encode_message(saved));
  EXPECT_TRUE(loaded->has_heading_bias);
  EXPECT_EQ(loaded->pose.frames, 4200);
}

TEST(PoseCheckpoint, AFileHoldingABarePoseLoadsWithoutTheBias) {
  testing::TempDir dir("checkpoint");
  const std::string path = dir.file("old.checkpoint");
  testing::write_file_bytes(path, encode_message(a_pose()));
  std::string problem;
  const auto loaded = PoseCheckpoint(path).load(&problem);
  ASSERT_TRUE(loaded.has_value()) << problem;
  EXPECT_FALSE(loaded->has_heading_bias);
  EXPECT_EQ(encode_message(loaded->pose), encode_message(a_pose()));
}

TEST(PoseCheckpoint, ADamagedFileIsNamedAndNotUsed) {
  testing::TempDir dir("checkpoint");
  const std::string path = dir.file("damaged.checkpoint");
  std::vector<uint8_t> bytes = encode_message(checkpoint_without_bias(a_pose()));
  bytes.resize(bytes.size() / 2);  // a torn write from something else
  testing::write_file_bytes(path, bytes);
  std::string problem;
  EXPECT_FALSE(PoseCheckpoint(path).load(&problem).has_value());
  EXPECT_NE(problem.find(path), std::string::npos) << problem;
  EXPECT_NE(problem.find("starting afresh"), std::string::npos) << problem;
}

TEST(PoseCheckpoint, AFailedWriteIsCountedAndNamed) {
  testing::TempDir dir("checkpoint");
  const std::string path = dir.file("no_such_folder/yaw_fusion.checkpoint");
  PoseCheckpoint checkpoint(path);
  checkpoint.save(checkpoint_without_bias(a_pose()));
  EXPECT_EQ(checkpoint.saves(), 0);
  EXPECT_EQ(checkpoint.save_errors(), 1);
  EXPECT_NE(checkpoint.last_error().find(path), std::string::npos) << checkpoint.last_error();
}

}  // namespace
}  // namespace nadir
