#include <gtest/gtest.h>

#include <cmath>

#include "sim/rng.h"
#include "sim/scene_motion.h"
#include "sim/tracker_model.h"
#include "sim/truth.h"

namespace mocap::sim {
namespace {

/// A tool 1.5 m in front of the tracker (NDI: -z), its markers facing it (body +z = tracker +z).
Rigid3d FacingTool(double depth_m = 1.5) {
  return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.05, -0.02, -depth_m));
}

TEST(TrackerModel, FitRigidRecoversAKnownTransform) {
  const MarkerBody body = DefaultCameraBody();
  const Rigid3d T = Rigid3d::FromRvec({0.3, -0.2, 1.1}, {0.1, 0.2, -1.4});
  std::vector<Eigen::Vector3d> measured;
  for (const auto& m : body.markers_m) measured.push_back(T * m);
  const Rigid3d fit = FitRigid(body.markers_m, measured);
  EXPECT_LT(TranslationDistanceM(fit, T), 1e-12);
  EXPECT_LT(RotationDistanceDeg(fit, T), 1e-9);
}

TEST(TrackerModel, MarkerNoiseHasTheConfiguredRmsAndPoseNoiseFollowsFromGeometry) {
  TrackerOptions options;
  options.noise_rms_mm = 0.25;
  const MarkerBody body = DefaultSimObjects().objects[0].body;
  const Rigid3d truth = FacingTool();
  Rng rng(7);
  double sum_fit_sq = 0, sum_centroid_sq = 0, sum_angle_sq = 0;
  const int n = 4000;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& m : body.markers_m) centroid += m / static_cast<double>(body.markers_m.size());
  for (int i = 0; i < n; ++i) {
    const TrackerMeasurement m = MeasureBody(body, truth, {}, options, rng);
    ASSERT_EQ(m.status, PoseStatus::kValid);
    sum_fit_sq += m.fit_rms_m * m.fit_rms_m;
    sum_centroid_sq += (m.T_tracker_body * centroid - truth * centroid).squaredNorm();
    sum_angle_sq += std::pow(RotationDistanceDeg(m.T_tracker_body, truth), 2);
  }
  const double markers = static_cast<double>(body.markers_m.size());
  // Residual of a 6-dof fit to N markers: E[rms^2] = sigma_3d^2 (N - 2) / N (3N - 6 of 3N dof left).
  EXPECT_NEAR(std::sqrt(sum_fit_sq / n), 0.25e-3 * std::sqrt((markers - 2) / markers), 0.05 * 0.25e-3);
  // The centroid of the fit averages N markers: RMS sigma_3d / sqrt(N).
  EXPECT_NEAR(std::sqrt(sum_centroid_sq / n), 0.25e-3 / std::sqrt(markers), 0.05 * 0.25e-3 / std::sqrt(markers));
  // Rotation noise exists and is small for a 6-10 cm tool (about sigma / radius).
  const double rotation_rms_deg = std::sqrt(sum_angle_sq / n);
  RecordProperty("rotation_rms_deg", std::to_string(rotation_rms_deg));
  EXPECT_GT(rotation_rms_deg, 0.05);
  EXPECT_LT(rotation_rms_deg, 0.5);
}

TEST(TrackerModel, ToolTurnedAwayIsMissing) {
  TrackerOptions options;
  const MarkerBody body = DefaultCameraBody();
  Rng rng(1);
  // 60 degrees away: still seen; 80 degrees: lost (limit 75).
  for (double angle : {60.0, 80.0}) {
    const Rigid3d turned = FacingTool() * Rigid3d::FromRvec({RadFromDeg(angle), 0, 0}, Eigen::Vector3d::Zero());
    const TrackerMeasurement m = MeasureBody(body, turned, {}, options, rng);
    if (angle < 75) {
      EXPECT_EQ(m.status, PoseStatus::kValid);
    } else {
      EXPECT_EQ(m.status, PoseStatus::kMissing);
      EXPECT_EQ(m.facing_away_markers, 4);
    }
  }
}

TEST(TrackerModel, OccluderOnTheLineOfSightHidesMarkers) {
  TrackerOptions options;
  const MarkerBody body = DefaultCameraBody();
  Rng rng(2);
  const OccluderBox hand{Rigid3d(Eigen::Quaterniond::Identity(), {0.05, 0.0, -1.2}), {0.2, 0.2, 0.02}};
  const TrackerMeasurement hidden = MeasureBody(body, FacingTool(), std::vector<OccluderBox>{hand}, options, rng);
  EXPECT_EQ(hidden.status, PoseStatus::kMissing);
  EXPECT_EQ(hidden.occluded_markers, 4);
  const OccluderBox aside{Rigid3d(Eigen::Quaterniond::Identity(), {0.6, 0.0, -1.2}), {0.2, 0.2, 0.02}};
  EXPECT_EQ(MeasureBody(body, FacingTool(), std::vector<OccluderBox>{aside}, options, rng).status, PoseStatus::kValid);
}

TEST(TrackerModel, VolumeGivesOutOfVolumeAndPartiallyInVolume) {
  TrackerOptions options;
  const MarkerBody body = DefaultCameraBody();
  Rng rng(3);
  EXPECT_EQ(MeasureBody(body, FacingTool(3.0), {}, options, rng).status, PoseStatus::kOutOfVolume);
  EXPECT_EQ(MeasureBody(body, FacingTool(0.5), {}, options, rng).status, PoseStatus::kOutOfVolume);
  // Straddling the far plane: two markers beyond it, pose still reported.
  const Rigid3d straddle = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2.2, Eigen::Vector3d::UnitY())), {0, 0, -2.38});
  const TrackerMeasurement m = MeasureBody(body, straddle, {}, options, rng);
  EXPECT_GT(m.out_of_volume_markers, 0);
  if (m.visible_markers >= 3) {
    EXPECT_EQ(m.status, PoseStatus::kPartiallyInVolume);
  }
  EXPECT_TRUE(options.volume.Contains({0.0, 0.0, -1.5}));
  EXPECT_FALSE(options.volume.Contains({0.0, 0.0, 1.5}));
  EXPECT_FALSE(options.volume.Contains({0.7, 0.0, -1.5}));  // beyond 1.5 * 0.783 / 2.4 = 0.49 m
}

TEST(TrackerStreams, DefaultSceneRateLatencyAndHandOcclusion) {
  const Scenario scenario = DefaultScenario();
  const SimObjects library = DefaultSimObjects();
  const std::vector<BodyStream> streams = SimulateTrackerStreams(SceneMotion(scenario), library);
  ASSERT_EQ(streams.size(), scenario.objects.size() + 1);
  EXPECT_EQ(streams[0].body, "camera_body");
  const BodyStream& camera = streams[0];
  // 60 Hz, stamped at measurement time + 14.2 ms.
  EXPECT_EQ(camera.samples[1].stamp_ns - camera.samples[0].stamp_ns, NsFromSeconds(1.0 / 60) );
  EXPECT_EQ(camera.samples[30].stamp_ns, NsFromSeconds(0.0) + NsFromSeconds(0.0142));
  for (const BodyStream& stream : streams) {
    SCOPED_TRACE(stream.body);
    EXPECT_GT(stream.valid_fraction(), 0.9);
    // Noise: fitted vs true pose within a few tenths of a millimetre.
    for (size_t k = 0; k < stream.samples.size(); k += 50)
      if (HasPose(stream.samples[k].status)) {
        EXPECT_LT(TranslationDistanceM(stream.samples[k].pose, stream.true_T_tracker_body[k]), 1e-3);
      }
  }
  // The hand hovers over the bottle's tool from 6.8 s to 7.2 s: the bottle is missing then, occluded.
  const BodyStream& bottle = streams.back();
  ASSERT_EQ(bottle.body, "bottle_body");
  const size_t at_7s = 30 + 7 * 60;
  EXPECT_EQ(bottle.samples[at_7s].status, PoseStatus::kMissing);
  EXPECT_GT(bottle.measurements[at_7s].occluded_markers, 1);
  EXPECT_EQ(bottle.samples[30 + 60].status, PoseStatus::kValid);
}

TEST(TrackerStreams, SameSeedSameSamples) {
  const Scenario scenario = DefaultScenario();
  const auto a = SimulateTrackerStreams(SceneMotion(scenario), DefaultSimObjects());
  const auto b = SimulateTrackerStreams(SceneMotion(scenario), DefaultSimObjects());
  for (size_t k = 0; k < a[1].samples.size(); k += 37)
    EXPECT_EQ(a[1].samples[k].pose.translation(), b[1].samples[k].pose.translation());
  Scenario other = scenario;
  other.options.seed += 1;
  const auto c = SimulateTrackerStreams(SceneMotion(other), DefaultSimObjects());
  EXPECT_NE(a[1].samples[5].pose.translation(), c[1].samples[5].pose.translation());
}

}  // namespace
}  // namespace mocap::sim
