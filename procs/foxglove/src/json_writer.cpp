#include "ucon/foxglove/json_writer.hpp"

#include <charconv>
#include <cmath>
#include <cstring>

namespace ucon {
namespace foxglove {

namespace {

// Length of the valid UTF-8 sequence starting at s[i] (1..4), or 0 if it is not one.
std::size_t utf8SequenceLength(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  std::size_t n;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;  // no overlong forms
    if (c == 0xED) hi = 0x9F;  // no surrogates
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;  // at most U+10FFFF
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  if (b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  }
  return n;
}

// Writes each element's shortest text straight into the output, grown once per array.
template <class F>
void numbers(std::string* out, const F* v, std::size_t n) {
  constexpr std::size_t kMax = 32;  // longest number text, plus the comma
  const std::size_t start = out->size();
  out->resize(start + 2 + n * kMax);
  char* p = &(*out)[start];
  *p++ = '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) *p++ = ',';
    if (std::isfinite(v[i])) {
      p = std::to_chars(p, p + kMax, v[i]).ptr;
    } else {
      std::memcpy(p, "null", 4);
      p += 4;
    }
  }
  *p++ = ']';
  out->resize(static_cast<std::size_t>(p - out->data()));
}

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

}  // namespace

void JsonWriter::beginObject() {
  separate();
  out_->push_back('{');
  need_comma_ = false;
}

void JsonWriter::endObject() {
  out_->push_back('}');
  need_comma_ = true;
}

void JsonWriter::beginArray() {
  separate();
  out_->push_back('[');
  need_comma_ = false;
}

void JsonWriter::endArray() {
  out_->push_back(']');
  need_comma_ = true;
}

void JsonWriter::key(std::string_view k) {
  separate();
  out_->push_back('"');
  out_->append(k);
  out_->append("\":", 2);
  need_comma_ = false;
}

void JsonWriter::integer(int64_t v) {
  separate();
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out_->append(buf, r.ptr);
}

namespace {
// Shortest text that reads back to the same value; null for NaN and infinity.
template <class F>
void appendNumber(std::string* out, F v) {
  if (!std::isfinite(v)) {
    out->append("null", 4);
    return;
  }
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out->append(buf, r.ptr);
}
}  // namespace

void JsonWriter::number(double v) {
  separate();
  appendNumber(out_, v);
}

void JsonWriter::number(float v) {
  separate();
  appendNumber(out_, v);
}

void JsonWriter::numberArray(const float* v, std::size_t n) {
  separate();
  numbers(out_, v, n);
}

void JsonWriter::numberArray(const double* v, std::size_t n) {
  separate();
  numbers(out_, v, n);
}

void JsonWriter::boolean(bool v) {
  separate();
  if (v) {
    out_->append("true", 4);
  } else {
    out_->append("false", 5);
  }
}

void JsonWriter::null() {
  separate();
  out_->append("null", 4);
}

void JsonWriter::string(std::string_view s) {
  separate();
  out_->push_back('"');
  std::size_t i = 0;
  while (i < s.size()) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x80 && c != '"' && c != '\\') {
      // Copy the run of plain ASCII in one go.
      std::size_t j = i + 1;
      while (j < s.size()) {
        const unsigned char d = static_cast<unsigned char>(s[j]);
        if (d < 0x20 || d >= 0x80 || d == '"' || d == '\\') break;
        ++j;
      }
      out_->append(s.data() + i, j - i);
      i = j;
      continue;
    }
    if (c == '"' || c == '\\') {
      out_->push_back('\\');
      out_->push_back(static_cast<char>(c));
      ++i;
    } else if (c < 0x20) {
      static constexpr char kHex[] = "0123456789abcdef";
      switch (c) {
        case '\n': out_->append("\\n", 2); break;
        case '\r': out_->append("\\r", 2); break;
        case '\t': out_->append("\\t", 2); break;
        case '\b': out_->append("\\b", 2); break;
        case '\f': out_->append("\\f", 2); break;
        default:
          out_->append("\\u00", 4);
          out_->push_back(kHex[c >> 4]);
          out_->push_back(kHex[c & 0xF]);
      }
      ++i;
    } else {
      const std::size_t n = utf8SequenceLength(s, i);
      if (n == 0) {
        out_->append("\xEF\xBF\xBD", 3);  // U+FFFD for a byte that is not valid UTF-8
        ++i;
      } else {
        out_->append(s.data() + i, n);
        i += n;
      }
    }
  }
  out_->push_back('"');
}

void JsonWriter::base64(const uint8_t* data, std::size_t size) {
  separate();
  out_->push_back('"');
  const std::size_t start = out_->size();
  out_->resize(start + base64Length(size));
  char* o = &(*out_)[start];
  std::size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    const uint32_t v = (uint32_t{data[i]} << 16) | (uint32_t{data[i + 1]} << 8) | data[i + 2];
    *o++ = kBase64[(v >> 18) & 63];
    *o++ = kBase64[(v >> 12) & 63];
    *o++ = kBase64[(v >> 6) & 63];
    *o++ = kBase64[v & 63];
  }
  if (i < size) {
    const uint32_t v = (uint32_t{data[i]} << 16) | (i + 1 < size ? uint32_t{data[i + 1]} << 8 : 0u);
    *o++ = kBase64[(v >> 18) & 63];
    *o++ = kBase64[(v >> 12) & 63];
    *o++ = i + 1 < size ? kBase64[(v >> 6) & 63] : '=';
    *o++ = '=';
  }
  out_->push_back('"');
}

}  // namespace foxglove
}  // namespace ucon
