#pragma once
// Where the emulated tracker's bodies are: a source of ground-truth poses over time. Scripted motion
// (static / circle / linear) is built in; a recorded tracker stream is served by RecordedTrajectory
// (recorded_trajectory.h).
//
// Script format (text, one statement per line, '#' starts a comment; lengths in mm as the tracker
// reports them, times in seconds since tracking started):
//   volume X_MIN X_MAX Y_MIN Y_MAX Z_MIN Z_MAX [MARGIN]   measurement volume; outside = out of volume,
//                                                         within MARGIN of a face = partially in volume
//   static NAME X Y Z [QW QX QY QZ]                       a body at rest
//   circle NAME CX CY CZ RADIUS PERIOD_S [PHASE_DEG]      circle in the x-y plane, yawing with the motion
//   linear NAME X Y Z VX VY VZ                            constant velocity (mm/s), fixed orientation
//   missing NAME START_S END_S                            the body is reported MISSING in [start, end)
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/rigid3.h"

namespace mocap::ndi {

/// Ground truth of one body at one time.
struct BodyState {
  Rigid3d T_tracker_body;  ///< metres
  bool forced_missing = false;
  /// Port-status bits to report besides the volume check (reply.h port_status: out of volume,
  /// partially in volume), for a source that knows them (a recording).
  uint32_t port_status_bits = 0;
};

class TrajectorySource {
 public:
  virtual ~TrajectorySource() = default;
  virtual int body_count() const = 0;
  virtual std::string body_name(int body) const = 0;
  /// Precondition: 0 <= body < body_count(), t_s >= 0 (seconds since tracking started). Must be
  /// thread-safe (const).
  virtual BodyState At(int body, double t_s) const = 0;
  /// Tracking time after which nothing more happens (a recording's last sample), if there is one.
  virtual std::optional<double> end_s() const { return std::nullopt; }
};

/// An axis-aligned measurement volume in the tracker frame (metres).
struct TrackingVolume {
  Eigen::Vector3d min_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_m = Eigen::Vector3d::Zero();
  double partial_margin_m = 0;
};

enum class MotionKind { kStatic, kCircle, kLinear };

struct BodyScript {
  std::string name;
  MotionKind kind = MotionKind::kStatic;
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();    ///< static/linear position, circle centre
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  double radius_m = 0;
  double period_s = 1;
  double phase_rad = 0;
  std::vector<std::pair<double, double>> missing_s;      ///< [start, end) intervals
};

struct TrajectoryScript {
  std::vector<BodyScript> bodies;
  std::optional<TrackingVolume> volume;
};

/// Parses the script text; `where` names it in errors ("file.txt" -> "file.txt:12: ..."). Throws InputError.
TrajectoryScript ParseTrajectoryScript(std::string_view text, const std::string& where);
/// Reads and parses a script file. Throws InputError.
TrajectoryScript LoadTrajectoryScript(const std::string& path);
/// `count` bodies on circles about (0, 0, -1.5 m), radii 100, 150, ... mm, periods 4, 5, ... s.
TrajectoryScript DefaultTrajectoryScript(int count);

class ScriptedTrajectory : public TrajectorySource {
 public:
  explicit ScriptedTrajectory(TrajectoryScript script) : script_(std::move(script)) {}
  int body_count() const override { return static_cast<int>(script_.bodies.size()); }
  std::string body_name(int body) const override { return script_.bodies.at(static_cast<size_t>(body)).name; }
  BodyState At(int body, double t_s) const override;
  const TrajectoryScript& script() const { return script_; }

 private:
  TrajectoryScript script_;
};

}  // namespace mocap::ndi
