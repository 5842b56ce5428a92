// Unit conversion at the edge, the trajectory script, and the emulated tracker's command handling.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "capture/ndi/commands.h"
#include "capture/ndi/convert.h"
#include "capture/ndi/emulated_tracker.h"
#include "capture/ndi/encode.h"
#include "capture/ndi/trajectory.h"
#include "core/check.h"

namespace mocap::ndi {
namespace {

HandleReport ValidReport() {
  HandleReport h;
  h.handle = 1;
  h.status = HandleStatus::kValid;
  h.has_transform = true;
  h.q_wxyz = {0.7072, 0, 0, 0.7072};  // rounded like NDI's: norm 1.0001
  h.t_mm = {10.5, -20.25, -1500};
  h.rms_error_mm = 0.12;
  h.has_port_status = true;
  h.port_status = 0x31;
  return h;
}

TEST(NdiConvert, MillimetresToMetresAndNormalisedQuaternion) {
  const HandleReport h = ValidReport();
  const std::optional<Rigid3d> pose = ToRigid3d(h);
  ASSERT_TRUE(pose);
  EXPECT_NEAR(pose->translation().x(), 0.0105, 1e-12);
  EXPECT_NEAR(pose->translation().z(), -1.5, 1e-12);
  EXPECT_NEAR(pose->rotation().norm(), 1.0, 1e-12);
  EXPECT_NEAR(pose->quat_wxyz()[3], std::sqrt(0.5), 1e-9);  // 90 degrees about z
  EXPECT_NEAR(RmsErrorM(h), 0.00012, 1e-12);
  EXPECT_EQ(ToPoseStatus(h), PoseStatus::kValid);
}

TEST(NdiConvert, StatusMapping) {
  HandleReport h = ValidReport();
  h.port_status |= port_status::kOutOfVolume;
  EXPECT_EQ(ToPoseStatus(h), PoseStatus::kOutOfVolume);
  h.port_status = 0x31 | port_status::kPartiallyInVolume;
  EXPECT_EQ(ToPoseStatus(h), PoseStatus::kPartiallyInVolume);
  h.status = HandleStatus::kMissing;
  h.has_transform = false;
  EXPECT_EQ(ToPoseStatus(h), PoseStatus::kMissing);
  EXPECT_FALSE(ToRigid3d(h));
  h.status = HandleStatus::kDisabled;
  EXPECT_EQ(ToPoseStatus(h), PoseStatus::kDisabled);
}

TEST(NdiConvert, NanOrFarFromUnitQuaternionIsMissingNotACrash) {
  HandleReport h = ValidReport();
  h.q_wxyz[0] = std::nan("");
  EXPECT_FALSE(ToRigid3d(h));
  EXPECT_EQ(ToPoseStatus(h), PoseStatus::kMissing);
  h = ValidReport();
  h.q_wxyz = {0.5, 0, 0, 0};
  EXPECT_FALSE(ToRigid3d(h));
}

TEST(NdiTrajectory, ParsesScriptAndEvaluatesMotion) {
  const TrajectoryScript script = ParseTrajectoryScript(R"(
# two bodies
volume -500 500 -500 500 -2000 -1000 50
static ref 0 0 -1500 1 0 0 0
circle tool 100 0 -1500 200 4 90   # phase 90 degrees
linear probe 0 0 -1200 10 0 0
missing tool 1.0 2.0
)", "test.txt");
  ASSERT_EQ(script.bodies.size(), 3u);
  ASSERT_TRUE(script.volume);
  EXPECT_NEAR(script.volume->partial_margin_m, 0.05, 1e-12);
  const ScriptedTrajectory trajectory(script);
  EXPECT_NEAR(trajectory.At(0, 3.0).T_tracker_body.translation().z(), -1.5, 1e-12);
  const BodyState tool = trajectory.At(1, 1.0);  // quarter period after 90 degrees: 180 degrees
  EXPECT_NEAR(tool.T_tracker_body.translation().x(), 0.1 - 0.2, 1e-9);
  EXPECT_TRUE(tool.forced_missing);
  EXPECT_FALSE(trajectory.At(1, 2.0).forced_missing);
  EXPECT_NEAR(trajectory.At(2, 2.0).T_tracker_body.translation().x(), 0.02, 1e-12);
}

TEST(NdiTrajectory, ErrorsNameTheLine) {
  auto message = [](const char* text) {
    try {
      ParseTrajectoryScript(text, "s.txt");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("static a 0 0 0\ncircle b 0 0 0 -5 2\n"), "s.txt:2: circle: RADIUS and PERIOD_S must be positive");
  EXPECT_NE(message("static a 0 0\n").find("s.txt:1: expected 3 to 7 numbers, got 2"), std::string::npos);
  EXPECT_NE(message("spiral a 0 0 0\n").find("s.txt:1: unknown statement 'spiral'"), std::string::npos);
  EXPECT_NE(message("missing a 0 1\n").find("no body named 'a'"), std::string::npos);
  EXPECT_NE(message("static a 0 0 x\n").find("expected a number"), std::string::npos);
  EXPECT_NE(message("# nothing\n").find("declares no body"), std::string::npos);
}

class EmulatedTrackerTest : public ::testing::Test {
 protected:
  std::string Send(std::string_view command, double t_s = 0) {
    return tracker_.Handle(FrameCommand(command), t_s).bytes;
  }
  std::shared_ptr<const TrajectorySource> trajectory_ =
      std::make_shared<ScriptedTrajectory>(DefaultTrajectoryScript(2));
  EmulatedTracker tracker_{EmulatedTrackerOptions{.rate_hz = 100, .preloaded_handles = false}, trajectory_};
};

TEST_F(EmulatedTrackerTest, ErrorRepliesForBadCommands) {
  EXPECT_EQ(tracker_.Handle("INIT:0000\r", 0).bytes, FrameErrorReply(0x04));  // bad CRC
  EXPECT_EQ(Send("PHSR:00"), FrameErrorReply(0x10));                          // before INIT
  EXPECT_EQ(Send("INIT:"), "OKAYA896\r");
  EXPECT_EQ(Send("FOO:12"), FrameErrorReply(0x01));
  EXPECT_EQ(Send("BX:0801"), FrameErrorReply(0x0C));  // not tracking
  EXPECT_EQ(Send("PINIT:0A"), FrameErrorReply(0x08));  // no such handle
  EXPECT_EQ(Send("PHRQ:*********1****"), FrameReply("0A"));
  EXPECT_EQ(Send("PINIT:0A"), FrameErrorReply(0x13));  // no tool definition uploaded yet
  EXPECT_EQ(Send("PENA:0AD"), FrameErrorReply(0x0E));  // not initialised
  EXPECT_EQ(Send("COMM:90000"), FrameErrorReply(0x23));
  EXPECT_EQ(Send("APIREV "), FrameReply("G.001.004"));
}

TEST_F(EmulatedTrackerTest, PassiveToolSetupThenBx) {
  Send("INIT:");
  EXPECT_EQ(Send("PHRQ:*********1****"), FrameReply("0A"));
  const std::vector<uint8_t> rom(100, 0x11);
  EXPECT_EQ(Send(PvwrCommand(0x0A, 0, std::span(rom).subspan(0, 64))), FrameReply("OKAY"));
  EXPECT_EQ(Send(PvwrCommand(0x0A, 64, std::span(rom).subspan(64))), FrameReply("OKAY"));
  EXPECT_EQ(Send("PHSR:02"), FrameReply("010A001"));
  EXPECT_EQ(Send("PINIT:0A"), FrameReply("OKAY"));
  EXPECT_EQ(Send("PHSR:03"), FrameReply("010A011"));
  EXPECT_EQ(Send("PENA:0AD"), FrameReply("OKAY"));
  EXPECT_EQ(Send("TSTART:"), FrameReply("OKAY"));
  const std::string bytes = Send("BX:0801", 0.505);
  const std::vector<uint8_t> frame(bytes.begin(), bytes.end());
  auto parsed = ParseBx(frame, 0x0801);
  ASSERT_TRUE(parsed.ok()) << parsed.error.ToString();
  ASSERT_EQ(parsed.value->handles.size(), 1u);
  const HandleReport& h = parsed.value->handles[0];
  EXPECT_EQ(h.handle, 0x0A);
  EXPECT_EQ(h.status, HandleStatus::kValid);
  EXPECT_EQ(h.frame_number, 1000u + 50u);
  const Rigid3d truth = trajectory_->At(0, 0.5).T_tracker_body;
  EXPECT_NEAR(h.t_mm[0], truth.translation().x() * 1e3, 1e-3);
  EXPECT_NEAR(h.t_mm[2], -1500.0, 1e-3);
}

TEST_F(EmulatedTrackerTest, GarbageCommandsGetErrorRepliesWithValidCrc) {
  Send("INIT:");
  Send("TSTART:");
  uint64_t state = 9;
  const std::string alphabet = "0123456789ABCDEF:* \rPHSRBXTINVWEQ";
  for (int trial = 0; trial < 3000; ++trial) {
    std::string line;
    for (int i = 0; i < trial % 40; ++i) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      line += alphabet[(state >> 33) % alphabet.size()];
    }
    if (trial % 2) line = FrameCommand(line);  // half of them with a correct CRC, reaching the handlers
    const EmulatorReply reply = tracker_.Handle(line, 1.0);
    ASSERT_FALSE(reply.bytes.empty());
    if (reply.tracking_data) continue;
    ASSERT_TRUE(ParseAsciiReply(reply.bytes).ok()) << line;
  }
}

TEST(NdiEmulatedTracker, VolumeAndForcedMissing) {
  TrajectoryScript script = ParseTrajectoryScript(
      "volume -100 100 -100 100 -2000 -1000 20\nstatic in 0 0 -1500\nstatic edge 90 0 -1500\n"
      "static out 300 0 -1500\nstatic gone 0 0 -1500\nmissing gone 0 10\n",
      "v");
  EmulatedTracker tracker({.volume = script.volume}, std::make_shared<ScriptedTrajectory>(script));
  EXPECT_EQ(tracker.Report(0, 1000, 0x0801).port_status, 0x31u);
  EXPECT_EQ(tracker.Report(1, 1000, 0x0801).port_status, 0x31u | port_status::kPartiallyInVolume);
  const HandleReport out = tracker.Report(2, 1000, 0x0801);
  EXPECT_EQ(out.status, HandleStatus::kValid);  // 0x0800: still reported, flagged out of volume
  EXPECT_EQ(out.port_status, 0x31u | port_status::kOutOfVolume);
  EXPECT_EQ(tracker.Report(2, 1000, 0x0001).status, HandleStatus::kMissing);
  EXPECT_EQ(tracker.Report(3, 1000, 0x0801).status, HandleStatus::kMissing);
}

TEST(NdiEmulatedTracker, NoiseAndDropoutAreRepeatablePerFrame) {
  auto trajectory = std::make_shared<ScriptedTrajectory>(DefaultTrajectoryScript(1));
  EmulatedTracker tracker({.noise_mm = 0.5, .dropout = 0.3, .seed = 7}, trajectory);
  int missing = 0;
  double sum_sq = 0;
  int valid = 0;
  for (uint32_t frame = 1000; frame < 3000; ++frame) {
    const HandleReport a = tracker.Report(0, frame, 0x0801), b = tracker.Report(0, frame, 0x0801);
    EXPECT_EQ(a.t_mm, b.t_mm);
    if (a.status == HandleStatus::kMissing) {
      ++missing;
      continue;
    }
    const Eigen::Vector3d truth = trajectory->At(0, tracker.TimeOfFrame(frame)).T_tracker_body.translation() * 1e3;
    sum_sq += (Eigen::Vector3d(a.t_mm[0], a.t_mm[1], a.t_mm[2]) - truth).squaredNorm() / 3;
    ++valid;
  }
  EXPECT_NEAR(missing / 2000.0, 0.3, 0.04);
  EXPECT_NEAR(std::sqrt(sum_sq / valid), 0.5, 0.05);
}

}  // namespace
}  // namespace mocap::ndi
