// TUM RGB-D fr1/desk (Kinect v1, motion-capture ground truth): frame-to-frame ICP of the static scene
// against the mocap relative camera pose, for the 8 consecutive pairs of the 9 stored depth frames.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/camera.h"
#include "validate/icp.h"

namespace mocap {
namespace {

const std::string kDir = std::string(MOCAP_SHARED_DIR) + "/realdata/tum_fr1_desk_9frames/";

struct Stamped {
  double t;
  Rigid3d T_world_camera;
};

std::vector<Stamped> ReadGroundTruth() {
  std::ifstream in(kDir + "groundtruth.txt");
  EXPECT_TRUE(in.good());
  std::vector<Stamped> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double t, x, y, z, qx, qy, qz, qw;
    s >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    out.push_back({t, Rigid3d::FromQuatXyzw(qx, qy, qz, qw, {x, y, z})});
  }
  return out;
}

Rigid3d PoseAt(const std::vector<Stamped>& gt, double t) {
  const auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const Stamped& s, double v) { return s.t < v; });
  EXPECT_TRUE(it != gt.begin() && it != gt.end());
  const Stamped& b = *it;
  const Stamped& a = *(it - 1);
  return Interpolate(a.T_world_camera, b.T_world_camera, (t - a.t) / (b.t - a.t));
}

PointCloud ReadDepthCloud(const std::string& file, const PinholeCamera& camera) {
  const cv::Mat raw = cv::imread(kDir + "depth/" + file, cv::IMREAD_UNCHANGED);
  EXPECT_EQ(raw.type(), CV_16UC1) << file;
  DepthImage depth(raw.cols, raw.rows, 0.0f);
  for (int v = 0; v < raw.rows; ++v)
    for (int u = 0; u < raw.cols; ++u) depth.at(u, v) = raw.at<uint16_t>(v, u) / 5000.0f;  // TUM: 5000 = 1 m
  return DepthToPoints(depth, camera);
}

struct PairErrors {
  std::vector<double> icp_mm, icp_deg, still_mm, still_deg;
};

PairErrors RunPairs(const PinholeCamera& camera) {
  const std::vector<Stamped> gt = ReadGroundTruth();
  const std::vector<std::string> stamps = {"1305031453.374112", "1305031453.404816", "1305031453.436941",
                                           "1305031453.473352", "1305031453.505218", "1305031453.538301",
                                           "1305031453.574074", "1305031453.605314", "1305031453.636951"};
  IcpOptions options;
  options.initial_correspondence_distance_m = 0.1;
  options.max_correspondence_distance_m = 0.02;
  options.max_iterations = 60;
  PairErrors e;
  PointCloud previous = VoxelDownsample(ReadDepthCloud(stamps[0] + ".png", camera), 0.005);
  for (size_t k = 1; k < stamps.size(); ++k) {
    const PointCloud current = VoxelDownsample(ReadDepthCloud(stamps[k] + ".png", camera), 0.005);
    const PointGrid target(previous);
    const IcpResult r = AlignPointToPoint(VoxelDownsample(current, 0.02), target, Rigid3d::Identity(), options);
    const Rigid3d truth = PoseAt(gt, std::stod(stamps[k - 1])).inverse() * PoseAt(gt, std::stod(stamps[k]));
    e.icp_mm.push_back(1e3 * TranslationDistanceM(r.T_target_source, truth));
    e.icp_deg.push_back(RotationDistanceDeg(r.T_target_source, truth));
    e.still_mm.push_back(1e3 * TranslationDistanceM(Rigid3d::Identity(), truth));
    e.still_deg.push_back(RotationDistanceDeg(Rigid3d::Identity(), truth));
    previous = current;
  }
  return e;
}

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST(TumFr1Desk, FrameToFrameIcpAgreesWithMocapRelativePose) {
  // fr1 colour intrinsics (the depth images are registered to the colour camera).
  const PinholeCamera fr1{640, 480, 517.3, 516.5, 318.6, 255.3, {}};
  const PairErrors e = RunPairs(fr1);
  const double mm = Median(e.icp_mm), deg = Median(e.icp_deg);
  std::printf("[TUM fr1/desk, fr1 intrinsics] frame-to-frame ICP vs mocap over 8 pairs: median %.1f mm, %.2f deg; "
              "max %.1f mm, %.2f deg (camera moved median %.1f mm, %.2f deg per frame)\n",
              mm, deg, *std::max_element(e.icp_mm.begin(), e.icp_mm.end()),
              *std::max_element(e.icp_deg.begin(), e.icp_deg.end()), Median(e.still_mm), Median(e.still_deg));
  // ICP must explain most of the motion: well below the motion itself, and within 1 cm / 1 deg.
  EXPECT_LT(mm, 0.5 * Median(e.still_mm));
  EXPECT_LT(deg, 0.5 * Median(e.still_deg));
  EXPECT_LT(mm, 10.0);
  EXPECT_LT(deg, 1.0);
}

TEST(TumFr1Desk, DefaultKinectIntrinsicsForComparison) {
  const PinholeCamera kinect{640, 480, 525.0, 525.0, 319.5, 239.5, {}};
  const PairErrors e = RunPairs(kinect);
  std::printf("[TUM fr1/desk, 525 intrinsics] frame-to-frame ICP vs mocap over 8 pairs: median %.1f mm, %.2f deg\n",
              Median(e.icp_mm), Median(e.icp_deg));
  EXPECT_LT(Median(e.icp_mm), 0.5 * Median(e.still_mm));
}

}  // namespace
}  // namespace mocap
