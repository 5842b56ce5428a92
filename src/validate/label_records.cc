// Reading a label run's labels.jsonl and summarising the record checks (session_check.h).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/check.h"
#include "validate/session_check.h"

namespace mocap {
namespace {

Eigen::Vector3d Vector3(const nlohmann::json& j, const std::string& field, const std::string& where) {
  if (!j.contains(field) || !j[field].is_array() || j[field].size() != 3)
    throw InputError(where, Str("field \"", field, "\" must be an array of 3 numbers"));
  return {j[field][0].get<double>(), j[field][1].get<double>(), j[field][2].get<double>()};
}

RecordCheck ParseRecord(const nlohmann::json& j, const std::string& where) {
  for (const char* field : {"camera", "index", "object", "instance"})
    if (!j.contains(field)) throw InputError(where, Str("missing field \"", field, "\""));
  RecordCheck r;
  r.camera = j["camera"].get<std::string>();
  r.index = j["index"].get<int64_t>();
  r.stamp_ns = j.value("stamp_ns", int64_t{0});
  r.object = j["object"].get<int>();
  r.name = j.value("name", std::string());
  r.instance = j["instance"].get<int>();
  if (r.instance <= 0 || r.instance > 65535) throw InputError(where, Str("instance id ", r.instance, " not in 1..65535"));
  r.T_camera_object_label = Rigid3d::FromRvec(Vector3(j, "rvec", where), Vector3(j, "t_m", where));
  return r;
}

}  // namespace

LabelRecordsFile ReadLabelRecords(const std::filesystem::path& labels_dir) {
  const std::filesystem::path file = labels_dir / "labels.jsonl";
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "cannot be opened; pass the folder `mocaplabel label --out` wrote");
  LabelRecordsFile out;
  std::string line;
  for (int64_t number = 1; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const std::string where = Str(file.string(), ":", number);
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where, Str("not a JSON record (", e.what(), ")"));
    }
    ++out.total;
    if (!j.contains("rvec")) continue;  // a label without a pose has nothing to check
    try {
      out.records.push_back(ParseRecord(j, where));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where, Str("malformed record (", e.what(), ")"));
    }
  }
  return out;
}

Stat ComputeStat(std::vector<double> values) {
  Stat s;
  s.count = static_cast<int64_t>(values.size());
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) { return values[static_cast<size_t>(std::lround(q * (values.size() - 1)))]; };
  s.median = values.size() % 2 ? values[values.size() / 2]
                               : 0.5 * (values[values.size() / 2 - 1] + values[values.size() / 2]);
  s.p95 = at(0.95);
  s.max = values.back();
  double mean = 0;
  for (double v : values) mean += v;
  mean /= values.size();
  double var = 0;
  for (double v : values) var += (v - mean) * (v - mean);
  s.std = std::sqrt(var / values.size());
  return s;
}

ValidationSummary Summarise(const std::vector<RecordCheck>& records, int64_t total_records) {
  ValidationSummary s;
  s.records = total_records;
  s.records_without_pose = total_records - static_cast<int64_t>(records.size());
  std::vector<double> position, axis, angle, label_score, iou, precision, recall;
  int64_t successes = 0;
  for (const RecordCheck& r : records) {
    const LabelCheck& c = r.check;
    ++s.verdicts[std::string(ToString(c.verdict))];
    ++s.reasons[std::string(ToString(c.reason_code))];
    if (c.estimated) {
      position.push_back(c.errors.position_mm);
      axis.push_back(c.errors.rotation_axis_deg);
      angle.push_back(c.errors.rotation_angle_deg);
    }
    if (!IsBadInput(c.reason_code)) {
      ++s.records_checked;
      successes += c.success ? 1 : 0;
      label_score.push_back(c.label_score);
    }
    if (r.segmentation) {
      iou.push_back(r.segmentation->iou);
      precision.push_back(r.segmentation->precision);
      recall.push_back(r.segmentation->recall);
    }
  }
  s.segicp_success_rate = s.records_checked > 0 ? static_cast<double>(successes) / s.records_checked : 0.0;
  s.position_error_mm = ComputeStat(position);
  s.rotation_axis_error_deg = ComputeStat(axis);
  s.rotation_angle_error_deg = ComputeStat(angle);
  s.label_score = ComputeStat(label_score);
  s.has_segmentation = !iou.empty();
  s.iou = ComputeStat(iou);
  s.precision = ComputeStat(precision);
  s.recall = ComputeStat(recall);
  return s;
}

}  // namespace mocap
