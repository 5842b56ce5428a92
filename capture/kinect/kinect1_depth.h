#pragma once
// Kinect1 depth units: the 11-bit raw disparity that libfreenect's FREENECT_DEPTH_11BIT mode delivers
// (and fakenect replays), and depth in millimetres (FREENECT_DEPTH_MM / _REGISTERED, 0 = no value).
//
// Without the device's own calibration tables (fakenect replay, or a libfreenect built without
// registration) raw values are converted with N. Burrus' fit used in libfreenect's examples/glpclview.c:
//   z [m] = 1 / (a * raw + b),  a = -0.0030711 m^-1 per step, b = 3.3309495 m^-1.
// Its inverse writes replay recordings (fakenect_recording.h). One disparity step at depth z spans
// dz = |a| z^2 (2.9 mm at 1 m, 12 mm at 2 m), so a round trip mm -> raw -> mm is exact to within half a step.
#include <array>
#include <cstdint>
#include <span>

#include <opencv2/core.hpp>

namespace mocap::capture {

inline constexpr uint16_t kKinect1RawNoValue = 2047;   ///< FREENECT_DEPTH_RAW_NO_VALUE
inline constexpr uint16_t kKinect1MaxDepthMm = 10000;  ///< FREENECT_DEPTH_MM_MAX_VALUE
inline constexpr double kBurrusA = -0.0030711;         ///< 1/m per raw step
inline constexpr double kBurrusB = 3.3309495;          ///< 1/m

/// Depth in metres of a raw 11-bit disparity by the Burrus fit; 0 when the value carries no depth
/// (2047, or outside the fit's range of positive depths up to kKinect1MaxDepthMm).
double Raw11ToDepthM(uint16_t raw);

/// Inverse of Raw11ToDepthM, rounded to the nearest step; kKinect1RawNoValue for depth_m <= 0 (no value)
/// or a depth the 11-bit code cannot carry (nearer than Raw11ToDepthM(0) = 0.300 m, farther than 10 m).
uint16_t DepthMToRaw11(double depth_m);

/// Size in metres of one disparity step at depth_m: |a| * z^2 (derivative of the fit).
double Raw11StepM(double depth_m);

/// Largest |z - Raw11ToDepthM(DepthMToRaw11(z))| at depth z from rounding to the nearest step (the far
/// side of half a step, the fit being convex), in metres.
double Raw11RoundTripErrorM(double depth_m);

/// A raw -> millimetre lookup table over all 2048 codes (0 = no value).
class Raw11ToMmTable {
 public:
  /// From the Burrus fit (replay, or no device calibration).
  static Raw11ToMmTable FromFit();
  /// From the device's own table (freenect_registration::raw_to_mm_shift, 2048 entries); entries above
  /// kKinect1MaxDepthMm become 0. Precondition: device_table.size() >= 2048.
  static Raw11ToMmTable FromDevice(std::span<const uint16_t> device_table);

  uint16_t operator[](uint16_t raw) const { return raw < table_.size() ? table_[raw] : 0; }
  /// Converts a buffer of width x height native-endian uint16 raw codes into a new CV_16UC1 image in mm.
  /// The buffer need not be 2-byte aligned (fakenect 0.5.3 hands out its file buffer past the PGM header).
  cv::Mat Convert(const void* raw, int width, int height) const;
  bool from_device() const { return from_device_; }

 private:
  std::array<uint16_t, 2048> table_{};
  bool from_device_ = false;
};

}  // namespace mocap::capture
