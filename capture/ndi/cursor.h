#pragma once
// Bounds-checked readers over reply bytes: every read says whether the bytes were there, so the parsers
// can report the offset of a short or malformed reply instead of reading past it.
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string_view>

namespace mocap::ndi {

/// Reads fixed-width fields of an ASCII reply.
class TextCursor {
 public:
  explicit TextCursor(std::string_view text) : text_(text) {}
  size_t offset() const { return pos_; }
  bool AtEnd() const { return pos_ == text_.size(); }
  size_t remaining() const { return text_.size() - pos_; }
  /// Consumes `literal` when the text continues with it.
  bool Take(std::string_view literal) {
    if (text_.substr(pos_, literal.size()) != literal) return false;
    pos_ += literal.size();
    return true;
  }
  /// Consumes everything up to and including `c` (or to the end).
  void SkipPast(char c) {
    const size_t at = text_.find(c, pos_);
    pos_ = at == std::string_view::npos ? text_.size() : at + 1;
  }
  /// `digits` hex digits (at most 8) as a number; nothing consumed on failure.
  std::optional<uint32_t> Hex(size_t digits) {
    if (digits > 8 || remaining() < digits) return std::nullopt;
    uint32_t value = 0;
    for (size_t i = 0; i < digits; ++i) {
      const char c = text_[pos_ + i];
      int v = -1;
      if (c >= '0' && c <= '9') v = c - '0';
      else if (c >= 'A' && c <= 'F') v = c - 'A' + 10;
      else if (c >= 'a' && c <= 'f') v = c - 'a' + 10;
      if (v < 0) return std::nullopt;
      value = value * 16 + static_cast<uint32_t>(v);
    }
    pos_ += digits;
    return value;
  }
  /// A sign ('+' or '-') and `digits` decimal digits, scaled by `scale`; nothing consumed on failure.
  std::optional<double> SignedDecimal(size_t digits, double scale) {
    if (remaining() < digits + 1) return std::nullopt;
    const char sign = text_[pos_];
    if (sign != '+' && sign != '-') return std::nullopt;
    int64_t value = 0;
    for (size_t i = 1; i <= digits; ++i) {
      const char c = text_[pos_ + i];
      if (c < '0' || c > '9') return std::nullopt;
      value = value * 10 + (c - '0');
    }
    pos_ += digits + 1;
    return (sign == '-' ? -1.0 : 1.0) * static_cast<double>(value) * scale;
  }

 private:
  std::string_view text_;
  size_t pos_ = 0;
};

/// Reads little-endian fields of a binary reply.
class ByteCursor {
 public:
  explicit ByteCursor(std::span<const uint8_t> bytes, size_t base_offset = 0) : bytes_(bytes), base_(base_offset) {}
  size_t offset() const { return base_ + pos_; }
  size_t remaining() const { return bytes_.size() - pos_; }
  bool Skip(size_t n) {
    if (remaining() < n) return false;
    pos_ += n;
    return true;
  }
  std::optional<uint8_t> U8() {
    if (remaining() < 1) return std::nullopt;
    return bytes_[pos_++];
  }
  std::optional<uint16_t> U16() {
    if (remaining() < 2) return std::nullopt;
    const uint16_t v = static_cast<uint16_t>(bytes_[pos_] | (bytes_[pos_ + 1] << 8));
    pos_ += 2;
    return v;
  }
  std::optional<uint32_t> U32() {
    if (remaining() < 4) return std::nullopt;
    uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | bytes_[pos_ + static_cast<size_t>(i)];
    pos_ += 4;
    return v;
  }
  std::optional<float> F32() {
    const std::optional<uint32_t> bits = U32();
    if (!bits) return std::nullopt;
    float value;
    std::memcpy(&value, &*bits, sizeof(value));
    return value;
  }

 private:
  std::span<const uint8_t> bytes_;
  size_t base_;
  size_t pos_ = 0;
};

}  // namespace mocap::ndi
