#pragma once
// Small parsing helpers shared by the importers. Every function that can fail on bad input throws
// InputError naming the place (`where`, usually "file:line"), so a malformed field is reported where
// it is, never read as zero.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/rigid3.h"

namespace mocap::import {

/// "path:line" for error messages (line counted from 1).
std::string Where(const std::filesystem::path& file, int64_t line);

/// Whole file as text. Throws InputError when it cannot be opened or read.
std::string ReadTextFile(const std::filesystem::path& file);

/// Splits `text` into lines; strips a trailing '\r' (CRLF files) from each.
std::vector<std::string_view> SplitLines(std::string_view text);

/// Fields separated by runs of spaces or tabs.
std::vector<std::string_view> SplitWhitespace(std::string_view line);

/// Fields separated by `separator`, kept as they are (empty fields stay, for CSV blanks).
std::vector<std::string_view> SplitFields(std::string_view line, char separator);

std::string_view Trim(std::string_view text);

/// A finite decimal number (the whole field). Throws InputError "not a number" otherwise.
double ParseDouble(std::string_view field, const std::string& where);

/// A decimal integer (the whole field).
int64_t ParseInt(std::string_view field, const std::string& where);

/// A time in seconds written as a decimal ("1305031453.359684", "-0.5", "1898165.1") converted to
/// integer nanoseconds without going through a double, so the 16 significant digits of a Unix time
/// survive exactly. Digits beyond the 9th decimal are rounded (half away from zero). Exponent notation
/// is accepted through a double. Throws InputError when it is not a number or out of range.
int64_t NanosecondsFromSeconds(std::string_view seconds, const std::string& where);

/// Rotation from a matrix read from a file, whose entries carry limited precision: accepted when
/// |R R^T - I| (Frobenius) <= `tolerance` and det(R) > 0, then projected onto the nearest rotation
/// (SVD). Throws InputError otherwise (not a rotation, a scaled matrix, a wrong-unit file).
Eigen::Quaterniond RotationFromNearlyOrthonormal(const Eigen::Matrix3d& R, const std::string& where,
                                                 double tolerance = 1e-3);

/// Unit quaternion from a file: accepted when |norm - 1| <= `tolerance`, then normalised. Throws
/// InputError otherwise (a missing component, a wrong order mixing in a translation).
Eigen::Quaterniond QuaternionNearlyUnit(double w, double x, double y, double z, const std::string& where,
                                        double tolerance = 1e-3);

}  // namespace mocap::import
