#include "calibrate/calibration_check.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "calibrate/check_model.h"
#include "calibrate/robust_stats.h"
#include "core/check.h"
#include "core/parallel_for.h"

namespace mocap {

using check_model::Fit;
using check_model::Item;
using check_model::ModelRecord;

std::string_view ToString(CheckItemKind kind) {
  switch (kind) {
    case CheckItemKind::kCameraMount: return "camera_mount";
    case CheckItemKind::kObjectMount: return "object_mount";
    case CheckItemKind::kLatency: return "latency";
  }
  return "?";
}

std::string MountSizeText(const CheckFinding& f) {
  const auto fixed = [](double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", value);
    return std::string(text);
  };
  std::string out;
  if (f.ci95_mm > 0) out = Str(fixed(f.size_mm), " mm (95 %: +-", fixed(f.ci95_mm), ")");
  if (f.ci95_deg > 0) out += Str(out.empty() ? "" : " and ", fixed(f.size_deg), " deg (95 %: +-", fixed(f.ci95_deg), ")");
  return out;
}

void CalibrationCheckOptions::check() const {
  if (!(min_mount_mm > 0)) throw InputError("CalibrationCheckOptions.min_mount_mm", "must be positive");
  if (!(min_camera_mount_deg > 0)) throw InputError("CalibrationCheckOptions.min_camera_mount_deg", "must be positive");
  if (!(min_object_mount_deg > 0)) throw InputError("CalibrationCheckOptions.min_object_mount_deg", "must be positive");
  if (!(max_spread_mm > 0)) throw InputError("CalibrationCheckOptions.max_spread_mm", "must be positive");
  if (!(max_spread_deg > 0)) throw InputError("CalibrationCheckOptions.max_spread_deg", "must be positive");
  if (!(min_latency_ms > 0)) throw InputError("CalibrationCheckOptions.min_latency_ms", "must be positive");
  if (!(significance > 0)) throw InputError("CalibrationCheckOptions.significance", "must be positive");
  if (min_records < 6) throw InputError("CalibrationCheckOptions.min_records", Str("is ", min_records, "; need >= 6"));
  if (max_items < 1) throw InputError("CalibrationCheckOptions.max_items", "must be at least 1");
  if (max_neighbour_gap_ns <= 0) throw InputError("CalibrationCheckOptions.max_neighbour_gap_ns", "must be positive");
  if (!(huber_sigmas > 0)) throw InputError("CalibrationCheckOptions.huber_sigmas", "must be positive");
  if (!(min_sigma_mm > 0) || !(min_sigma_deg > 0)) throw InputError("CalibrationCheckOptions.min_sigma_mm", "floors must be positive");
  if (!(similar_share > 0 && similar_share <= 1)) throw InputError("CalibrationCheckOptions.similar_share", "must be in (0, 1]");
}

namespace {

using check_model::ResidualAutocorrelation;

struct Candidate {
  Item item;
  Fit fit;
  double gain = 0;
};

using check_model::Part;

std::string ItemName(const check_model::Prepared& prepared, const Item& item) {
  const std::string part = item.part == Part::kRotation ? " (rotation)" : " (translation)";
  if (item.kind == CheckItemKind::kCameraMount) return "camera mount of " + prepared.cameras[static_cast<size_t>(item.index)] + part;
  if (item.kind == CheckItemKind::kObjectMount) return "object mount of " + prepared.objects[static_cast<size_t>(item.index)] + part;
  return "tracker latency";
}

const std::array<double, 6>& BlockOf(const Fit& fit, const Item& item) {
  return item.kind == CheckItemKind::kCameraMount ? fit.params.camera[static_cast<size_t>(item.index)]
                                                  : fit.params.object[static_cast<size_t>(item.index)];
}

/// An item's size (mm, deg, or signed ms for the latency) and the half-width of its 95 % interval, from
/// a fit in which it is free (its covariance at `slot`), widened by the autocorrelation factor. The
/// interval of a vector's length is taken along its direction (or the widest axis when it is zero).
struct PartSize {
  double size = 0, ci95 = INFINITY;
  Eigen::Vector3d measured = Eigen::Vector3d::Zero();  ///< a mount part's vector within what the records measure
};

/// `v` within the directions the records measure: those a mount part's covariance gives variance to (the
/// pseudo-inverse's: none for a direction no record measures, see check_model::FitItems), to a 95 %
/// half-width of at most `max_ci95`. A direction measured more loosely than the smallest error worth
/// reporting is left out: it is hardly measured, and a fit free along it can wander far (a funnel's
/// mount turned 45 deg about its axis of revolution, whose spin no record measures, while each record's
/// spin removal holds only to first order).
Eigen::Vector3d MeasuredPart(const Eigen::Matrix3d& cov, const Eigen::Vector3d& v, double max_ci95) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const double variance = eig.eigenvalues()(i);
    if (variance > 1e-9 * eig.eigenvalues().maxCoeff() && 1.96 * std::sqrt(variance) <= max_ci95)
      out += eig.eigenvectors().col(i) * eig.eigenvectors().col(i).dot(v);
  }
  return out;
}

/// The smallest error of an item worth reporting, in the units it is reported in (ms, mm, deg).
double MinReported(const Item& item, const CalibrationCheckOptions& o) {
  if (item.kind == CheckItemKind::kLatency) return o.min_latency_ms;
  if (item.part == Part::kTranslation) return o.min_mount_mm;
  return item.kind == CheckItemKind::kCameraMount ? o.min_camera_mount_deg : o.min_object_mount_deg;
}
PartSize SizeOf(const Item& item, const Fit& fit, size_t slot, double widen, const CalibrationCheckOptions& o) {
  const bool has_cov = slot < fit.covariance.size();
  if (item.kind == CheckItemKind::kLatency)
    return {1e3 * fit.params.latency_s,
            has_cov && fit.covariance[slot](0, 0) > 0 ? 1e3 * 1.96 * widen * std::sqrt(fit.covariance[slot](0, 0)) : INFINITY};
  const std::array<double, 6>& p = BlockOf(fit, item);
  const int first = item.part == Part::kRotation ? 0 : 3;
  const Eigen::Vector3d v(p[first], p[first + 1], p[first + 2]);
  const double unit = item.part == Part::kRotation ? DegFromRad(1.0) : 1e3;
  if (!has_cov) return {unit * v.norm(), INFINITY, v};
  const Eigen::Matrix3d cov = fit.covariance[slot];
  if (!(cov.diagonal().maxCoeff() > 0)) return {0.0, INFINITY};  // nothing of it is measured
  const Eigen::Vector3d measured = MeasuredPart(cov * widen * widen, v, MinReported(item, o) / unit);
  const double se = measured.norm() > 0 ? std::sqrt(std::max(0.0, measured.normalized().dot(cov * measured.normalized())))
                                        : std::sqrt(std::max(0.0, cov.diagonal().maxCoeff()));
  return {unit * measured.norm(), unit * 1.96 * widen * se, measured};
}

/// Large enough to matter and significant (z standard errors; the interval is 1.96 of them).
bool Reportable(const Item& item, const PartSize& s, const CalibrationCheckOptions& o) {
  const double z = o.significance / 1.96;
  return std::abs(s.size) >= MinReported(item, o) && std::abs(s.size) > z * s.ci95;
}

std::vector<Item> CandidateItems(const check_model::Prepared& prepared, int min_moving) {
  std::vector<Item> items;
  for (const Part part : {Part::kTranslation, Part::kRotation}) {
    for (int c = 0; c < static_cast<int>(prepared.cameras.size()); ++c) items.push_back({CheckItemKind::kCameraMount, c, part});
    for (int k = 0; k < static_cast<int>(prepared.objects.size()); ++k) items.push_back({CheckItemKind::kObjectMount, k, part});
  }
  int moving = 0;
  // A latency error shows only where the label moves (1 mm/s or 0.1 deg/s at least).
  for (const ModelRecord& m : prepared.records)
    moving += m.has_motion && (m.v_m_per_s.norm() > 1e-3 || m.w_rad_per_s.norm() > RadFromDeg(0.1)) ? 1 : 0;
  if (moving >= min_moving) items.push_back({CheckItemKind::kLatency, 0, Part::kTranslation});
  return items;
}

/// Each remaining candidate fitted together with the items already in, best gain first.
std::vector<Candidate> RankCandidates(const check_model::Prepared& prepared, const std::vector<Item>& in,
                                      const std::vector<Item>& all, double current_cost, double huber) {
  std::vector<Candidate> ranked;
  for (const Item& item : all)
    if (std::find(in.begin(), in.end(), item) == in.end()) ranked.push_back({item, {}, 0.0});
  // The fits are independent (each its own problem, solved on one thread): in parallel, the same results.
  ParallelFor(static_cast<int>(ranked.size()), 0, [&](int i) {
    std::vector<Item> free = in;
    free.push_back(ranked[i].item);
    ranked[i].fit = check_model::FitItems(prepared.records, static_cast<int>(prepared.cameras.size()),
                                          static_cast<int>(prepared.objects.size()), free, huber);
    ranked[i].gain = current_cost - ranked[i].fit.cost;
  });
  std::sort(ranked.begin(), ranked.end(), [](const Candidate& a, const Candidate& b) { return a.gain > b.gain; });
  return ranked;
}

std::vector<ResidualSummary> Summaries(const check_model::Prepared& prepared, const check_model::Params& after) {
  check_model::Params zero = after;
  for (auto& c : zero.camera) c.fill(0);
  for (auto& o : zero.object) o.fill(0);
  zero.latency_s = 0;
  std::map<std::pair<int, int>, std::array<std::vector<double>, 4>> groups;
  for (const ModelRecord& m : prepared.records) {
    const Eigen::Matrix<double, 6, 1> b = check_model::Residual(m, zero), a = check_model::Residual(m, after);
    auto& g = groups[{m.camera, m.object}];
    g[0].push_back(1e3 * b.tail<3>().norm()), g[1].push_back(DegFromRad(b.head<3>().norm()));
    g[2].push_back(1e3 * a.tail<3>().norm()), g[3].push_back(DegFromRad(a.head<3>().norm()));
  }
  std::vector<ResidualSummary> out;
  for (const auto& [key, g] : groups)
    out.push_back({prepared.cameras[static_cast<size_t>(key.first)], prepared.objects[static_cast<size_t>(key.second)],
                   static_cast<int>(g[0].size()), Median(g[0]), Median(g[1]), Median(g[2]), Median(g[3])});
  return out;
}

/// The records without those of objects whose residual scales exceed the spread bounds (named in
/// result.objects_left_out, with a warning each).
std::vector<CheckRecord> WithoutScatteredObjects(std::span<const CheckRecord> records, const CalibrationCheckOptions& options,
                                                 CalibrationCheckResult& result) {
  const check_model::Prepared all = check_model::Prepare(records, options);
  std::vector<bool> out(all.objects.size(), false);
  for (const ModelRecord& m : all.records) {
    const bool scattered = m.sigma_m > 1e-3 * options.max_spread_mm || m.sigma_rad > RadFromDeg(options.max_spread_deg);
    if (scattered && !out[static_cast<size_t>(m.object)]) {
      out[static_cast<size_t>(m.object)] = true;
      const std::string& name = all.objects[static_cast<size_t>(m.object)];
      result.objects_left_out.push_back(name);
      result.warnings.push_back(Str("left out ", name, ": its estimates scatter by ", 1e3 * m.sigma_m, " mm / ", DegFromRad(m.sigma_rad),
                                    " deg (robust sigma), so the depth does not pin its pose (a plane, or hardly visible)"));
    }
  }
  std::vector<CheckRecord> kept;
  for (size_t i = 0; i < records.size(); ++i)
    if (!out[static_cast<size_t>(all.records[i].object)]) kept.push_back(records[i]);
  return kept;
}

/// The items let in, one finding per mount (its parts merged) and one for the latency, in the order
/// their first part came in.
std::vector<CheckFinding> Findings(const check_model::Prepared& prepared, const std::vector<Item>& in, const std::vector<double>& gains,
                                   const std::vector<std::vector<std::string>>& alike, const Fit& fit, double widen, double base_cost,
                                   const CalibrationCheckOptions& options) {
  std::vector<CheckFinding> findings;
  std::vector<std::pair<CheckItemKind, int>> keys;
  for (size_t i = 0; i < in.size(); ++i) {
    const std::pair<CheckItemKind, int> key{in[i].kind, in[i].index};
    auto at = std::find(keys.begin(), keys.end(), key);
    if (at == keys.end()) {
      keys.push_back(key), findings.emplace_back();
      at = keys.end() - 1;
    }
    CheckFinding& f = findings[static_cast<size_t>(at - keys.begin())];
    f.kind = in[i].kind;
    f.explained_share += base_cost > 0 ? gains[i] / base_cost : 0;
    f.alike.insert(f.alike.end(), alike[i].begin(), alike[i].end());
    const PartSize size = SizeOf(in[i], fit, i, widen, options);
    if (in[i].kind == CheckItemKind::kLatency) {
      f.latency_error_ms = size.size, f.latency_ci95_ms = size.ci95;
      continue;
    }
    f.name = in[i].kind == CheckItemKind::kCameraMount ? prepared.cameras[static_cast<size_t>(in[i].index)]
                                                       : prepared.objects[static_cast<size_t>(in[i].index)];
    // The correction holds what the records measure of each part let in (a part not let in stays zero).
    Eigen::Matrix<double, 6, 1> p = Eigen::Matrix<double, 6, 1>::Zero();
    for (size_t j = 0; j < in.size(); ++j)
      if (in[j].kind == in[i].kind && in[j].index == in[i].index)
        p.segment<3>(in[j].part == Part::kRotation ? 0 : 3) = SizeOf(in[j], fit, j, widen, options).measured;
    f.correction = Rigid3d::FromRvec(p.head<3>(), p.tail<3>());
    if (in[i].part == Part::kRotation) f.size_deg = size.size, f.ci95_deg = size.ci95;
    else f.size_mm = size.size, f.ci95_mm = size.ci95;
  }
  return findings;
}

}  // namespace

CalibrationCheckResult CheckCalibration(std::span<const CheckRecord> records, const CalibrationCheckOptions& options) {
  options.check();
  if (static_cast<int>(records.size()) < options.min_records)
    throw InputError("calibration check", Str("too few reliable SegICP estimates: ", records.size(), " (need ", options.min_records,
                                              "); validate more frames (--frame-stride 1) or a longer session"));
  CalibrationCheckResult result;
  const std::vector<CheckRecord> kept = WithoutScatteredObjects(records, options, result);
  if (static_cast<int>(kept.size()) < options.min_records)
    throw InputError("calibration check", Str("too few reliable SegICP estimates: ", kept.size(), " (need ", options.min_records,
                                              ") once the objects whose estimates scatter are left out"));
  const check_model::Prepared prepared = check_model::Prepare(kept, options);
  result.records = static_cast<int>(kept.size());
  for (const ModelRecord& m : prepared.records) result.records_with_motion += m.has_motion ? 1 : 0;
  const std::vector<Item> all = CandidateItems(prepared, options.min_records);
  const int cameras = static_cast<int>(prepared.cameras.size()), objects = static_cast<int>(prepared.objects.size());
  const double base_cost = check_model::CostWithoutItems(prepared.records, cameras, objects, options.huber_sigmas);
  double cost = base_cost;
  std::vector<Item> in;
  std::vector<double> gains;
  std::vector<std::vector<std::string>> alike;
  Fit fit = check_model::FitItems(prepared.records, cameras, objects, {}, options.huber_sigmas);
  while (static_cast<int>(in.size()) < options.max_items) {
    std::vector<Candidate> ranked = RankCandidates(prepared, in, all, cost, options.huber_sigmas);
    // The best candidate that is reportable: one that explains more but is too small to matter (an
    // object's SegICP bias) must not hide it.
    std::vector<bool> reportable;
    for (const Candidate& c : ranked)
      reportable.push_back(c.gain > 0 && Reportable(c.item, SizeOf(c.item, c.fit, in.size(), ArWidening(ResidualAutocorrelation(prepared, c.fit.params)), options),
                                                    options));
    const size_t best = static_cast<size_t>(std::find(reportable.begin(), reportable.end(), true) - reportable.begin());
    if (best == ranked.size()) break;
    std::vector<std::string> names;  // other reportable items that explain almost as much
    for (size_t j = 0; j < ranked.size(); ++j)
      if (j != best && reportable[j] && ranked[j].gain >= options.similar_share * ranked[best].gain)
        names.push_back(ItemName(prepared, ranked[j].item));
    in.push_back(ranked[best].item), gains.push_back(ranked[best].gain), alike.push_back(names);
    cost = ranked[best].fit.cost;
    fit = std::move(ranked[best].fit);
  }
  result.autocorrelation = ResidualAutocorrelation(prepared, fit.params);
  result.findings = Findings(prepared, in, gains, alike, fit, ArWidening(result.autocorrelation), base_cost, options);
  for (size_t i = 0; i < in.size(); ++i)
    if (!alike[i].empty())
      result.warnings.push_back(Str(ItemName(prepared, in[i]), " and ", alike[i].front(),
                                    " explain the residuals almost equally well: record with the camera moving around several objects"));
  result.residuals = Summaries(prepared, fit.params);
  if (result.records_with_motion < options.min_records)
    result.warnings.push_back("too few consecutive validated frames to judge the latency: validate with --frame-stride 1");
  return result;
}

}  // namespace mocap
