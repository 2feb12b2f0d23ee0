#include "ucon/mot/mot_challenge.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>

namespace ucon {
namespace mot {
namespace {

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : line) {
    if (ch == ',' || ch == ' ' || ch == '\t' || ch == '\r') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(ch);
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

bool toDouble(const std::string& s, double* out) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || errno == ERANGE) return false;
  *out = v;
  return true;
}

}  // namespace

std::optional<MotFrames> parseMotChallenge(const std::string& text, const std::string& source,
                                           std::string* error) {
  MotFrames frames;
  std::size_t pos = 0;
  int line_no = 0;
  auto fail = [&](const std::string& what) {
    if (error) *error = source + ":" + std::to_string(line_no) + ": " + what;
    return std::nullopt;
  };
  static const char* kNames[6] = {"frame", "id", "x", "y", "w", "h"};
  while (pos <= text.size()) {
    const std::size_t nl = text.find('\n', pos);
    const std::string line = text.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos);
    pos = (nl == std::string::npos) ? text.size() + 1 : nl + 1;
    ++line_no;
    const auto fields = splitFields(line);
    if (fields.empty()) continue;
    if (fields.size() < 6) return fail("expected at least 6 fields (frame,id,x,y,w,h), got " +
                                       std::to_string(fields.size()));
    double v[6];
    for (int k = 0; k < 6; ++k) {
      if (!toDouble(fields[k], &v[k]) || !std::isfinite(v[k]))
        return fail(std::string("field '") + kNames[k] + "' is not a finite number: '" + fields[k] + "'");
    }
    if (v[0] < 1.0 || v[0] != std::floor(v[0])) return fail("frame must be an integer >= 1");
    if (v[1] != std::floor(v[1])) return fail("id must be an integer");
    if (v[4] < 0.0 || v[5] < 0.0) return fail("negative box width or height");
    Box b;
    b.id = static_cast<int64_t>(v[1]);
    b.x = v[2];
    b.y = v[3];
    b.w = v[4];
    b.h = v[5];
    frames[static_cast<int64_t>(v[0])].push_back(b);
  }
  return frames;
}

ClearMotSummary evaluateBoxes(const MotFrames& ground_truth, const MotFrames& predictions,
                              double min_iou) {
  std::set<int64_t> frame_ids;
  for (const auto& kv : ground_truth) frame_ids.insert(kv.first);
  for (const auto& kv : predictions) frame_ids.insert(kv.first);
  static const std::vector<Box> kNone;
  ClearMotAccumulator acc;
  for (int64_t f : frame_ids) {
    auto g = ground_truth.find(f);
    auto p = predictions.find(f);
    acc.updateBoxes(g == ground_truth.end() ? kNone : g->second,
                    p == predictions.end() ? kNone : p->second, min_iou);
  }
  return acc.summary();
}

}  // namespace mot
}  // namespace ucon
