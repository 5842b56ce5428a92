#include "capture/kinect/kinect1_depth.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "core/check.h"

namespace mocap::capture {

double Raw11ToDepthM(uint16_t raw) {
  if (raw >= kKinect1RawNoValue) return 0.0;
  const double inverse_depth = kBurrusA * raw + kBurrusB;
  if (inverse_depth <= 0.0) return 0.0;
  const double depth_m = 1.0 / inverse_depth;
  return depth_m * 1000.0 > kKinect1MaxDepthMm ? 0.0 : depth_m;
}

uint16_t DepthMToRaw11(double depth_m) {
  if (!(depth_m > 0.0) || !std::isfinite(depth_m)) return kKinect1RawNoValue;
  const long raw = std::lround((1.0 / depth_m - kBurrusB) / kBurrusA);
  if (raw < 0 || raw >= kKinect1RawNoValue) return kKinect1RawNoValue;
  // Rounding may land just beyond the 10 m limit; such a code would read back as "no value".
  if (Raw11ToDepthM(static_cast<uint16_t>(raw)) == 0.0) return kKinect1RawNoValue;
  return static_cast<uint16_t>(raw);
}

double Raw11StepM(double depth_m) { return -kBurrusA * depth_m * depth_m; }

double Raw11RoundTripErrorM(double depth_m) {
  // Half a step towards larger raw codes lowers 1/z by |a|/2; on the far side z grows the most.
  const double far_inverse = 1.0 / depth_m + 0.5 * kBurrusA;
  if (far_inverse <= 0.0) return std::numeric_limits<double>::infinity();
  return 1.0 / far_inverse - depth_m;
}

Raw11ToMmTable Raw11ToMmTable::FromFit() {
  Raw11ToMmTable table;
  for (size_t raw = 0; raw < table.table_.size(); ++raw)
    table.table_[raw] = static_cast<uint16_t>(std::lround(Raw11ToDepthM(static_cast<uint16_t>(raw)) * 1000.0));
  return table;
}

Raw11ToMmTable Raw11ToMmTable::FromDevice(std::span<const uint16_t> device_table) {
  MOCAP_CHECK(device_table.size() >= 2048, "device raw-to-mm table has ", device_table.size(), " entries");
  Raw11ToMmTable table;
  for (size_t raw = 0; raw < table.table_.size(); ++raw) {
    const uint16_t mm = device_table[raw];
    table.table_[raw] = (raw >= kKinect1RawNoValue || mm > kKinect1MaxDepthMm) ? 0 : mm;
  }
  table.from_device_ = true;
  return table;
}

cv::Mat Raw11ToMmTable::Convert(const void* raw, int width, int height) const {
  cv::Mat depth_mm(height, width, CV_16UC1);
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  const auto* bytes = static_cast<const unsigned char*>(raw);
  auto* out = depth_mm.ptr<uint16_t>();
  for (size_t i = 0; i < count; ++i) {
    uint16_t code;
    std::memcpy(&code, bytes + 2 * i, sizeof(code));
    out[i] = (*this)[code];
  }
  return depth_mm;
}

}  // namespace mocap::capture
