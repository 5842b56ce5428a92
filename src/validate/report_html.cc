// The static HTML report of `mocaplabel validate`: summary tables and inline SVG plots, no scripts and
// no external resources except the label run's overlay images (linked relatively).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "validate/report_html.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string Num(double value, int digits = 2) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value);
  return buffer;
}

const char* VerdictColour(Verdict v) {
  return v == Verdict::kAccept ? "#2a9d4b" : v == Verdict::kSuspect ? "#e0a100" : "#c8312e";
}

/// A histogram of `values` over [0, limit] in 24 bins; values beyond the limit go to the last bin.
std::string Histogram(const std::vector<double>& values, double limit, const std::string& unit,
                      double threshold) {
  constexpr int kBins = 24, kW = 480, kH = 160, kPad = 30;
  std::vector<int> bins(kBins, 0);
  for (double v : values) bins[std::min(kBins - 1, static_cast<int>(v / limit * kBins))]++;
  const int top = std::max(1, *std::max_element(bins.begin(), bins.end()));
  std::ostringstream s;
  s << "<svg width='" << kW + 2 * kPad << "' height='" << kH + 2 * kPad << "' xmlns='http://www.w3.org/2000/svg'>";
  const double bw = static_cast<double>(kW) / kBins;
  for (int b = 0; b < kBins; ++b) {
    const double h = static_cast<double>(bins[b]) / top * kH;
    s << "<rect x='" << kPad + b * bw << "' y='" << kPad + kH - h << "' width='" << bw - 1 << "' height='" << h
      << "' fill='#4a78b5'><title>" << bins[b] << "</title></rect>";
  }
  const double tx = kPad + std::min(1.0, threshold / limit) * kW;
  s << "<line x1='" << tx << "' y1='" << kPad << "' x2='" << tx << "' y2='" << kPad + kH
    << "' stroke='#c8312e' stroke-dasharray='4'/>";
  s << "<text x='" << kPad << "' y='" << kH + kPad + 18 << "' font-size='11'>0</text><text x='" << kPad + kW - 60
    << "' y='" << kH + kPad + 18 << "' font-size='11'>&gt;= " << Num(limit, 1) << " " << unit << "</text>";
  s << "<text x='" << kPad << "' y='" << kPad - 8 << "' font-size='11'>max bin " << top << " records; dashed: accept threshold "
    << Num(threshold, 1) << " " << unit << "</text></svg>";
  return s.str();
}

/// Position error per frame of one instance, dots coloured by verdict (errors clipped at `limit_mm`).
std::string Timeline(const std::vector<const RecordCheck*>& track, double limit_mm) {
  constexpr int kW = 640, kH = 120, kPad = 30;
  int64_t first = track.front()->index, last = track.front()->index;
  for (const RecordCheck* r : track) first = std::min(first, r->index), last = std::max(last, r->index);
  const double span = std::max<int64_t>(1, last - first);
  std::ostringstream s;
  s << "<svg width='" << kW + 2 * kPad << "' height='" << kH + 2 * kPad << "' xmlns='http://www.w3.org/2000/svg'>"
    << "<rect x='" << kPad << "' y='" << kPad << "' width='" << kW << "' height='" << kH << "' fill='none' stroke='#bbb'/>";
  for (const RecordCheck* r : track) {
    const double x = kPad + (r->index - first) / span * kW;
    const double e = r->check.estimated ? std::min(limit_mm, r->check.errors.position_mm) : limit_mm;
    const double y = kPad + kH - e / limit_mm * kH;
    s << "<circle cx='" << x << "' cy='" << y << "' r='3' fill='" << VerdictColour(r->check.verdict) << "'><title>frame "
      << r->index << ": " << Escape(r->check.reason) << "</title></circle>";
  }
  s << "<text x='" << kPad << "' y='" << kH + kPad + 16 << "' font-size='11'>frame " << first << "</text><text x='"
    << kPad + kW - 70 << "' y='" << kH + kPad + 16 << "' font-size='11'>frame " << last << "</text><text x='" << kPad
    << "' y='" << kPad - 8 << "' font-size='11'>position error, mm (top = " << Num(limit_mm, 0)
    << " or no estimate)</text></svg>";
  return s.str();
}

std::string SummaryTable(const ValidationSummary& s) {
  std::ostringstream o;
  o << "<table><tr><th>records</th><td>" << s.records << " (" << s.records_without_pose << " without a pose, "
    << s.records_checked << " checked)</td></tr>";
  if (!s.nothing_checked_why.empty())
    o << "<tr><th>nothing checked</th><td>" << Escape(s.nothing_checked_why) << "</td></tr>";
  else
    o << "<tr><th>SegICP success rate</th><td>" << Num(100 * s.segicp_success_rate, 1) << " %</td></tr>";
  for (const auto& [v, n] : s.verdicts) o << "<tr><th>" << v << "</th><td>" << n << "</td></tr>";
  for (const auto& [r, n] : s.reasons) o << "<tr><th>reason " << Escape(r) << "</th><td>" << n << "</td></tr>";
  const auto stat = [&](const char* name, const Stat& st, int digits) {
    o << "<tr><th>" << name << "</th><td>median " << Num(st.median, digits) << ", p95 " << Num(st.p95, digits)
      << ", std " << Num(st.std, digits) << " (" << st.count << ")</td></tr>";
  };
  stat("position error, mm", s.position_error_mm, 2);
  stat("rotation axis error, deg", s.rotation_axis_error_deg, 2);
  stat("rotation angle error, deg", s.rotation_angle_error_deg, 2);
  stat("label score a(M, S)", s.label_score, 3);
  if (s.has_segmentation) {
    stat("mask IoU", s.iou, 3);
    stat("mask precision", s.precision, 3);
    stat("mask recall", s.recall, 3);
  }
  o << "</table>";
  return o.str();
}

/// Rejects first, then suspects, each by decreasing position error; at most `count`.
std::vector<const RecordCheck*> Worst(const std::vector<RecordCheck>& records, size_t count) {
  std::vector<const RecordCheck*> out;
  for (const RecordCheck& r : records)
    if (r.check.verdict != Verdict::kAccept) out.push_back(&r);
  std::sort(out.begin(), out.end(), [](const RecordCheck* a, const RecordCheck* b) {
    if (a->check.verdict != b->check.verdict) return a->check.verdict == Verdict::kReject;
    return a->check.errors.position_mm > b->check.errors.position_mm;
  });
  if (out.size() > count) out.resize(count);
  return out;
}

std::string WorstTable(const std::vector<RecordCheck>& records, const fs::path& out_dir) {
  std::ostringstream o;
  o << "<table><tr><th>camera</th><th>frame</th><th>object</th><th>instance</th><th>verdict</th><th>reason</th><th>overlay</th></tr>";
  for (const RecordCheck* r : Worst(records, 20)) {
    o << "<tr><td>" << Escape(r->camera) << "</td><td>" << r->index << "</td><td>" << Escape(r->name) << " ("
      << r->object << ")</td><td>" << r->instance << "</td><td style='color:" << VerdictColour(r->check.verdict) << "'>"
      << ToString(r->check.verdict) << "</td><td>" << Escape(r->check.reason) << "</td><td>";
    if (!r->overlay.empty())
      o << "<img src='" << Escape(fs::relative(fs::absolute(r->overlay), fs::absolute(out_dir)).generic_string())
        << "' width='320'>";
    else
      o << "(label run without --overlay)";
    o << "</td></tr>";
  }
  o << "</table>";
  return o.str();
}

}  // namespace

std::string ValidationReportHtml(const SessionValidation& validation, const VerdictOptions& verdict,
                                 const fs::path& out_dir) {
  const ValidationSummary& s = validation.summary;
  std::vector<double> position, angle;
  for (const RecordCheck& r : validation.records)
    if (r.check.estimated) {
      position.push_back(r.check.errors.position_mm);
      angle.push_back(r.check.errors.rotation_angle_deg);
    }
  std::ostringstream o;
  o << "<!DOCTYPE html><html><head><meta charset='utf-8'><title>mocaplabel validate</title><style>"
       "body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}th,td{border:1px solid #ccc;"
       "padding:3px 8px;text-align:left;vertical-align:top}</style></head><body><h1>Label validation (SegICP)</h1>";
  o << "<h2>Summary</h2>" << SummaryTable(s);
  o << "<h2>Error distributions (SegICP estimate against the label)</h2><h3>Position, mm</h3>"
    << Histogram(position, std::max(4 * verdict.accept_position_m * 1e3, s.position_error_mm.p95), "mm",
                 verdict.accept_position_m * 1e3)
    << "<h3>Rotation angle, deg</h3>"
    << Histogram(angle, std::max(4 * verdict.accept_rotation_deg, s.rotation_angle_error_deg.p95), "deg",
                 verdict.accept_rotation_deg);
  o << "<h2>Per-frame timeline per object</h2><p>green accept, amber suspect, red reject</p>";
  std::map<std::pair<std::string, int>, std::vector<const RecordCheck*>> tracks;
  for (const RecordCheck& r : validation.records) tracks[{r.camera, r.instance}].push_back(&r);
  for (const auto& [key, track] : tracks)
    o << "<h3>" << Escape(key.first) << ": " << Escape(track.front()->name) << ", instance " << key.second << "</h3>"
      << Timeline(track, 4 * verdict.reject_position_m * 1e3);
  o << "<h2>Worst records</h2>" << WorstTable(validation.records, out_dir) << "</body></html>\n";
  return o.str();
}

}  // namespace mocap
