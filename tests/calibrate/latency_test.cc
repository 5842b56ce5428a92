#include "calibrate/latency.h"

#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "core/check.h"
#include "synthetic.h"

namespace mocap {
namespace {

using test::ExpSO3;

using test::kBoardbodyBoard;
using test::kCambodyCamera;
const Rigid3d kTrackerCambody(ExpSO3(Eigen::Vector3d(0.3, 0.1, -0.2)), Eigen::Vector3d(0.5, 0.2, 1.0));

/// The board held in front of the static camera and waved: T_camera_board at physical time t (s),
/// turning about all three axes (amplitude scaled by `amplitude`) around the board's centre.
Rigid3d TrueCameraBoard(double t, double amplitude) {
  const Eigen::Vector3d w = amplitude * Eigen::Vector3d(RadFromDeg(20) * std::sin(2 * M_PI * 0.7 * t + 0.3),
                                                        RadFromDeg(15) * std::sin(2 * M_PI * 1.1 * t + 1.9),
                                                        RadFromDeg(10) * std::sin(2 * M_PI * 0.9 * t + 4.0));
  const Eigen::Vector3d centre_board(0.16, 0.12, 0);
  const Eigen::Quaterniond facing(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d centre_camera(0.05 * std::sin(2 * M_PI * 0.4 * t), 0.03 * std::cos(2 * M_PI * 0.5 * t), 0.8);
  const Eigen::Quaterniond R = facing * ExpSO3(w);
  return Rigid3d(R, centre_camera - R * centre_board);
}

struct Recording {
  std::vector<StampedBoardPose> image_poses;
  std::vector<PoseSample> cambody, boardbody;
};

struct Rates {
  double tracker_hz = 60;
  double stamp_jitter_ms = 0;  ///< uniform +- on every camera and tracker stamp
};

/// 12 s: camera frames at 30 Hz stamped at exposure time (image pose noise 0.05 deg, 0.5 mm), tracker
/// samples stamped `latency_ms` after their measurement (noise 0.15 mm, 0.03 deg).
Recording Record(double latency_ms, double amplitude, unsigned seed, const Rates& rates = {}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter_s(-rates.stamp_jitter_ms * 1e-3, rates.stamp_jitter_ms * 1e-3);
  Recording rec;
  for (int k = 0; k * (1.0 / 30) < 12.0; ++k) {
    const double t = k / 30.0;
    rec.image_poses.push_back({std::llround((t + jitter_s(rng)) * 1e9), test::Noisy(TrueCameraBoard(t, amplitude), rng, 0.5e-3, 0.05)});
  }
  for (int j = 0; j * (1.0 / rates.tracker_hz) < 12.0; ++j) {
    const double measured_s = j / rates.tracker_hz;
    const int64_t stamp_ns = std::llround((measured_s + latency_ms * 1e-3 + jitter_s(rng)) * 1e9);
    const Rigid3d B = kTrackerCambody * kCambodyCamera * TrueCameraBoard(measured_s, amplitude) * kBoardbodyBoard.inverse();
    rec.cambody.push_back({stamp_ns, PoseStatus::kValid, test::Noisy(kTrackerCambody, rng, 0.15e-3, 0.03)});
    rec.boardbody.push_back({stamp_ns, PoseStatus::kValid, test::Noisy(B, rng, 0.15e-3, 0.03)});
  }
  return rec;
}

class LatencyCases : public ::testing::TestWithParam<std::tuple<double, unsigned, double, double>> {};

TEST_P(LatencyCases, FindsTheTrackerLatencyWithinAMillisecond) {
  const auto [latency_ms, seed, tracker_hz, jitter_ms] = GetParam();
  Recording rec = Record(latency_ms, 1.0, seed, Rates{tracker_hz, jitter_ms});
  const LatencyResult result = EstimateTrackerLatency(rec.image_poses, RelativePoseFromStreams(rec.cambody, rec.boardbody));
  const double error_ms = result.tracker_latency_ns * 1e-6 - latency_ms;
  std::printf("latency %.1f ms seed %u tracker %.1f Hz jitter %.1f ms: estimate %.3f ms (error %+.3f ms), rms %.3f deg, contrast %.1f, %d pairs\n",
              latency_ms, seed, tracker_hz, jitter_ms, result.tracker_latency_ns * 1e-6, error_ms, result.rms_deg, result.contrast, result.pairs_used);
  EXPECT_LT(std::abs(error_ms), 1.0);
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
  EXPECT_GT(result.pairs_used, 250);
  EXPECT_EQ(result.coarse_cost_deg.size(), 201u);
}

INSTANTIATE_TEST_SUITE_P(Cases, LatencyCases,
                         ::testing::Values(std::make_tuple(23.4, 1u, 60.0, 0.0), std::make_tuple(-37.9, 2u, 60.0, 0.0),
                                           std::make_tuple(0.0, 3u, 60.0, 0.0), std::make_tuple(141.7, 4u, 60.0, 0.0),
                                           std::make_tuple(14.2, 5u, 250.0, 0.5), std::make_tuple(-12.3, 6u, 57.1, 1.0)));

TEST(Latency, WarnsWhenTheBoardHardlyMoves) {
  Recording rec = Record(20.0, 0.02, 5);
  const LatencyResult result = EstimateTrackerLatency(rec.image_poses, RelativePoseFromStreams(rec.cambody, rec.boardbody));
  ASSERT_FALSE(result.warnings.empty());
  EXPECT_NE(result.warnings.front().find("hardly turns"), std::string::npos) << result.warnings.front();
}

TEST(Latency, TooShortARecordingIsAnInputError) {
  Recording rec = Record(20.0, 1.0, 6);
  rec.image_poses.resize(20);  // 0.66 s of frames
  try {
    EstimateTrackerLatency(rec.image_poses, RelativePoseFromStreams(rec.cambody, rec.boardbody));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too few frame pairs"), std::string::npos) << e.what();
  }
}

TEST(LatencyOptions, CheckNamesTheField) {
  LatencyOptions options;
  options.coarse_step_ns = 0;
  try {
    options.check();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("coarse_step_ns"), std::string::npos);
  }
}

}  // namespace
}  // namespace mocap
