#include "capture/ndi/trajectory.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/check.h"

namespace mocap::ndi {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Reads `count` numbers (mm or s as the statement says); throws naming the position.
std::vector<double> Numbers(std::istringstream& in, size_t count, size_t optional, const std::string& where,
                            const std::string& usage) {
  std::vector<double> values;
  double v;
  while (in >> v) values.push_back(v);
  if (!in.eof()) throw InputError(where, "expected a number; usage: " + usage);
  if (values.size() < count || values.size() > count + optional)
    throw InputError(where, Str("expected ", count, optional ? Str(" to ", count + optional) : "", " numbers, got ",
                                values.size(), "; usage: ", usage));
  for (double x : values)
    if (!std::isfinite(x)) throw InputError(where, "numbers must be finite");
  return values;
}

Eigen::Vector3d Mm(double x, double y, double z) { return Eigen::Vector3d(x, y, z) * 1e-3; }

BodyScript& FindBody(TrajectoryScript& script, const std::string& name, const std::string& where) {
  for (BodyScript& body : script.bodies)
    if (body.name == name) return body;
  throw InputError(where, "no body named '" + name + "' (declare it before 'missing')");
}

void ParseStatement(const std::string& keyword, std::istringstream& in, const std::string& where, TrajectoryScript& script) {
  if (keyword == "volume") {
    const auto v = Numbers(in, 6, 1, where, "volume X_MIN X_MAX Y_MIN Y_MAX Z_MIN Z_MAX [MARGIN]");
    TrackingVolume volume{Mm(v[0], v[2], v[4]), Mm(v[1], v[3], v[5]), v.size() > 6 ? v[6] * 1e-3 : 0.0};
    if ((volume.max_m - volume.min_m).minCoeff() <= 0) throw InputError(where, "volume: each MIN must be below its MAX");
    script.volume = volume;
    return;
  }
  std::string name;
  if (!(in >> name)) throw InputError(where, "'" + keyword + "' needs a body name");
  if (keyword == "missing") {
    const auto v = Numbers(in, 2, 0, where, "missing NAME START_S END_S");
    if (v[1] <= v[0]) throw InputError(where, "missing: END_S must be after START_S");
    FindBody(script, name, where).missing_s.emplace_back(v[0], v[1]);
    return;
  }
  for (const BodyScript& body : script.bodies)
    if (body.name == name) throw InputError(where, "body '" + name + "' declared twice");
  BodyScript body;
  body.name = name;
  if (keyword == "static") {
    const auto v = Numbers(in, 3, 4, where, "static NAME X Y Z [QW QX QY QZ]");
    if (v.size() != 3 && v.size() != 7) throw InputError(where, "static: give a position, or a position and QW QX QY QZ");
    body.origin_m = Mm(v[0], v[1], v[2]);
    if (v.size() == 7) {
      body.rotation = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);
      if (body.rotation.norm() < 1e-6) throw InputError(where, "static: zero quaternion");
      body.rotation.normalize();
    }
  } else if (keyword == "circle") {
    const auto v = Numbers(in, 5, 1, where, "circle NAME CX CY CZ RADIUS PERIOD_S [PHASE_DEG]");
    if (v[3] <= 0 || v[4] <= 0) throw InputError(where, "circle: RADIUS and PERIOD_S must be positive");
    body = BodyScript{name, MotionKind::kCircle, Mm(v[0], v[1], v[2]), Eigen::Quaterniond::Identity(),
                      Eigen::Vector3d::Zero(), v[3] * 1e-3, v[4], v.size() > 5 ? v[5] * kPi / 180 : 0.0, {}};
  } else if (keyword == "linear") {
    const auto v = Numbers(in, 6, 0, where, "linear NAME X Y Z VX VY VZ");
    body.kind = MotionKind::kLinear;
    body.origin_m = Mm(v[0], v[1], v[2]);
    body.velocity_mps = Mm(v[3], v[4], v[5]);
  } else {
    throw InputError(where, "unknown statement '" + keyword + "' (volume, static, circle, linear, missing)");
  }
  script.bodies.push_back(body);
}

}  // namespace

TrajectoryScript ParseTrajectoryScript(std::string_view text, const std::string& where) {
  TrajectoryScript script;
  std::istringstream lines{std::string(text)};
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::string keyword;
    if (!(in >> keyword)) continue;
    ParseStatement(keyword, in, Str(where, ":", number), script);
  }
  if (script.bodies.empty()) throw InputError(where, "the script declares no body (static, circle or linear)");
  if (script.bodies.size() > 200) throw InputError(where, "more than 200 bodies");
  return script;
}

TrajectoryScript LoadTrajectoryScript(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError(path, "cannot open the trajectory script");
  std::stringstream text;
  text << file.rdbuf();
  return ParseTrajectoryScript(text.str(), path);
}

TrajectoryScript DefaultTrajectoryScript(int count) {
  MOCAP_CHECK(count >= 1 && count <= 200, "body count ", count);
  TrajectoryScript script;
  for (int i = 0; i < count; ++i) {
    BodyScript body{Str("body", i + 1), MotionKind::kCircle, Mm(0, 0, -1500), Eigen::Quaterniond::Identity(),
                    Eigen::Vector3d::Zero(), (100.0 + 50.0 * i) * 1e-3, 4.0 + i, i * 0.7, {}};
    script.bodies.push_back(body);
  }
  return script;
}

BodyState ScriptedTrajectory::At(int body_index, double t_s) const {
  const BodyScript& body = script_.bodies.at(static_cast<size_t>(body_index));
  BodyState state;
  for (const auto& [start, end] : body.missing_s) state.forced_missing |= t_s >= start && t_s < end;
  switch (body.kind) {
    case MotionKind::kStatic:
      state.T_tracker_body = Rigid3d(body.rotation, body.origin_m);
      break;
    case MotionKind::kLinear:
      state.T_tracker_body = Rigid3d(body.rotation, body.origin_m + body.velocity_mps * t_s);
      break;
    case MotionKind::kCircle: {
      const double angle = body.phase_rad + 2 * kPi * t_s / body.period_s;
      const Eigen::Vector3d offset(body.radius_m * std::cos(angle), body.radius_m * std::sin(angle), 0);
      state.T_tracker_body = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())),
                                     body.origin_m + offset);
      break;
    }
  }
  return state;
}

}  // namespace mocap::ndi
