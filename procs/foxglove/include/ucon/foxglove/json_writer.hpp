#pragma once
/// @file json_writer.hpp
/// A streaming JSON text writer: appends to a std::string without building a document first
/// (a 20 000-point cloud is written in one pass). Numbers use the shortest text that reads back
/// to the same value; NaN and infinity, which JSON cannot represent, are written as null.
/// Strings are escaped and made valid UTF-8 (a byte that is not part of a valid UTF-8 sequence
/// becomes U+FFFD), so a corrupt message never produces invalid JSON.

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace ucon {
namespace foxglove {

class JsonWriter {
 public:
  /// Appends to *out (not cleared).
  explicit JsonWriter(std::string* out) : out_(out) {}

  void beginObject();
  void endObject();
  void beginArray();
  void endArray();
  /// Object key. `k` is written as it is: pass identifiers (no quotes, backslashes or control
  /// characters), as every key of the ucon types and the Foxglove schemas is.
  void key(std::string_view k);

  void integer(int64_t v);
  /// Shortest round-trip text; null for NaN and infinity.
  void number(double v);
  /// Shortest text that reads back to the same float; null for NaN and infinity.
  void number(float v);
  void boolean(bool v);
  void string(std::string_view s);
  void null();
  /// Bytes as a base64 string (RFC 4648, with padding).
  void base64(const uint8_t* data, std::size_t size);

  /// Whole arrays in one pass (the point arrays of a cloud): the same text as beginArray(),
  /// one number()/integer() per element, endArray().
  void numberArray(const float* v, std::size_t n);
  void numberArray(const double* v, std::size_t n);
  template <class Int>
  void integerArray(const Int* v, std::size_t n);

  /// Shorthands for key(k) followed by the value.
  void field(std::string_view k, int64_t v) { key(k); integer(v); }
  void field(std::string_view k, int v) { key(k); integer(v); }
  void field(std::string_view k, double v) { key(k); number(v); }
  void field(std::string_view k, bool v) { key(k); boolean(v); }
  void field(std::string_view k, std::string_view v) { key(k); string(v); }
  void field(std::string_view k, const char* v) { key(k); string(v); }

 private:
  void separate() {
    if (need_comma_) out_->push_back(',');
    need_comma_ = true;
  }
  std::string* out_;
  bool need_comma_ = false;
};

template <class Int>
void JsonWriter::integerArray(const Int* v, std::size_t n) {
  separate();
  constexpr std::size_t kMax = 21;  // "-9223372036854775808" and the comma
  const std::size_t start = out_->size();
  out_->resize(start + 2 + n * kMax);
  char* p = &(*out_)[start];
  *p++ = '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) *p++ = ',';
    p = std::to_chars(p, p + kMax, static_cast<int64_t>(v[i])).ptr;
  }
  *p++ = ']';
  out_->resize(static_cast<std::size_t>(p - out_->data()));
}

/// Number of characters base64 needs for `size` bytes.
inline std::size_t base64Length(std::size_t size) { return (size + 2) / 3 * 4; }

}  // namespace foxglove
}  // namespace ucon
