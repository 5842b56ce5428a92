// Summarising the record checks (session_check.h).
#include <algorithm>
#include <cmath>
#include <map>

#include "core/check.h"
#include "validate/session_check.h"

namespace mocap {

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

namespace {

/// One sentence for a run where no record could be checked: the commonest reason (of `reasons`, the
/// summary's counts), with the first record's own explanation of it.
std::string WhyNothingChecked(const std::vector<RecordCheck>& records, int64_t total_records,
                              const std::map<std::string, int64_t>& reasons) {
  if (total_records == 0) return "the label run has no records";
  if (records.empty()) return Str("none of the ", total_records, " label records has a pose");
  const auto commonest = std::max_element(reasons.begin(), reasons.end(),
                                          [](const auto& a, const auto& b) { return a.second < b.second; });
  const auto example = std::find_if(records.begin(), records.end(),
                                    [&](const RecordCheck& r) { return ToString(r.check.reason_code) == commonest->first; });
  return Str(commonest->second, " of ", records.size(), " records with a pose had unusable input (", commonest->first,
             ": ", example->check.reason, ")");
}

}  // namespace

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
    if (r.label_shift_ns != 0) ++s.labels_moved_to_depth_time;
    else if (r.depth_offset_ns != 0) ++s.labels_not_movable_to_depth_time;
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
  if (s.records_checked == 0) s.nothing_checked_why = WhyNothingChecked(records, total_records, s.reasons);
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
