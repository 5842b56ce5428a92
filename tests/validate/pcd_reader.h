#pragma once
// A small reader for PCD files (ascii, binary, binary_compressed) used by the tests and the bench to
// load the PCL fixture clouds; only the x, y, z float fields are read.
#include <string>

#include "validate/point_cloud.h"

namespace mocap::testing {

struct PcdCloud {
  int width = 0;
  int height = 0;
  /// One entry per point in file order (row-major for organised clouds); NaN points keep NaN.
  PointCloud points;
};

/// Throws InputError naming the file and the problem.
PcdCloud ReadPcd(const std::string& path);

/// The finite points only.
PointCloud FinitePoints(const PointCloud& points);

}  // namespace mocap::testing
