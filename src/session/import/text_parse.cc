#include "session/import/text_parse.h"

#include <Eigen/SVD>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/check.h"
#include "core/text.h"

namespace mocap::import {

std::string Where(const std::filesystem::path& file, int64_t line) { return Str(file.string(), ":", line); }

std::string ReadTextFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "cannot open the file (does it exist and is it readable?)");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(file.string(), "read error");
  return text.str();
}

std::vector<std::string_view> SplitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

std::vector<std::string_view> SplitWhitespace(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

std::vector<std::string_view> SplitFields(std::string_view line, char separator) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t end = line.find(separator, start);
    if (end == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, end - start));
    start = end + 1;
  }
}

std::string_view Trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
  return text;
}

double ParseDouble(std::string_view field, const std::string& where) {
  field = Trim(field);
  double value = 0.0;
  const char* begin = field.data();
  const char* end = field.data() + field.size();
  if (!field.empty() && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (field.empty() || ec != std::errc() || ptr != end || !std::isfinite(value))
    throw InputError(where, Str(QuoteForMessage(field), " is not a number"));
  return value;
}

int64_t ParseInt(std::string_view field, const std::string& where) {
  field = Trim(field);
  int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (field.empty() || ec != std::errc() || ptr != field.data() + field.size())
    throw InputError(where, Str(QuoteForMessage(field), " is not an integer"));
  return value;
}

int64_t NanosecondsFromSeconds(std::string_view seconds, const std::string& where) {
  const std::string_view text = Trim(seconds);
  if (text.find_first_of("eE") != std::string_view::npos) {
    const double s = ParseDouble(text, where);
    if (std::abs(s) > 9.2e9) throw InputError(where, Str("time ", QuoteForMessage(text), " s is out of range"));
    return static_cast<int64_t>(std::llround(s * 1e9));
  }
  size_t i = 0;
  const bool negative = !text.empty() && text[0] == '-';
  if (!text.empty() && (text[0] == '-' || text[0] == '+')) ++i;
  int64_t whole = 0;
  int64_t fraction_ns = 0;
  int whole_digits = 0;
  int fraction_digits = 0;
  bool round_up = false;
  for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i, ++whole_digits) {
    if (whole > (std::numeric_limits<int64_t>::max() / 1'000'000'000 - 9) / 10)
      throw InputError(where, Str("time ", QuoteForMessage(text), " s is out of range"));
    whole = whole * 10 + (text[i] - '0');
  }
  if (i < text.size() && text[i] == '.') {
    for (++i; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i, ++fraction_digits) {
      if (fraction_digits < 9) fraction_ns = fraction_ns * 10 + (text[i] - '0');
      else if (fraction_digits == 9) round_up = text[i] >= '5';
    }
  }
  if (i != text.size() || whole_digits + fraction_digits == 0)
    throw InputError(where, Str(QuoteForMessage(text), " is not a time in seconds"));
  for (int d = std::min(fraction_digits, 9); d < 9; ++d) fraction_ns *= 10;
  const int64_t ns = whole * 1'000'000'000 + fraction_ns + (round_up ? 1 : 0);
  return negative ? -ns : ns;
}

Eigen::Quaterniond RotationFromNearlyOrthonormal(const Eigen::Matrix3d& R, const std::string& where,
                                                 double tolerance) {
  const double orthogonality = (R * R.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (!(orthogonality <= tolerance) || !(R.determinant() > 0))
    throw InputError(where, Str("not a rotation matrix (|R R^T - I| = ", orthogonality, ", det = ",
                                R.determinant(), "); is the matrix scaled or in the wrong order?"));
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d nearest = svd.matrixU() * svd.matrixV().transpose();
  return Eigen::Quaterniond(nearest).normalized();
}

Eigen::Quaterniond QuaternionNearlyUnit(double w, double x, double y, double z, const std::string& where,
                                        double tolerance) {
  const Eigen::Quaterniond q(w, x, y, z);
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= tolerance))
    throw InputError(where, Str("quaternion (w x y z) = (", w, " ", x, " ", y, " ", z, ") has norm ", norm,
                                ", not 1; are the columns in the right order?"));
  return q.normalized();
}

}  // namespace mocap::import
