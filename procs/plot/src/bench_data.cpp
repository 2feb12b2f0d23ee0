#include "ucon/plot/bench_data.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ucon {
namespace plot {

const char* toString(BenchKind k) {
  switch (k) {
    case BenchKind::kPlanning: return "planning";
    case BenchKind::kPerception: return "perception";
  }
  return "?";
}

const char* toString(BenchStatus s) {
  switch (s) {
    case BenchStatus::kOk: return "ok";
    case BenchStatus::kOpenFailed: return "cannot open";
    case BenchStatus::kParseError: return "not valid JSON";
    case BenchStatus::kNoResults: return "no results";
    case BenchStatus::kUnknownKind: return "unknown benchmark";
  }
  return "?";
}

BenchStatus parseBenchJson(const std::string& text, BenchTable* out, std::string* error) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    if (error) *error = std::string("invalid JSON at byte ") + std::to_string(e.byte) + ": " + e.what();
    return BenchStatus::kParseError;
  }
  if (!doc.is_object() || !doc.contains("results") || !doc["results"].is_array()) {
    if (error) *error = "no \"results\" array";
    return BenchStatus::kNoResults;
  }
  BenchTable t;
  bool any_success = false, any_mota = false;
  for (const auto& r : doc["results"]) {
    if (!r.is_object()) {
      ++t.skipped_rows;
      continue;
    }
    BenchRow row;
    row.method = r.contains("method") && r["method"].is_string() ? r["method"].get<std::string>() : "ucon";
    if (r.contains("n_dynamic") && r["n_dynamic"].is_number_integer()) row.n_dynamic = r["n_dynamic"].get<int>();
    for (auto it = r.begin(); it != r.end(); ++it) {
      if (!it.value().is_number()) continue;  // null (NaN in the bench), strings, objects
      const double v = it.value().get<double>();
      if (std::isfinite(v)) row.values[it.key()] = v;
    }
    any_success = any_success || row.values.count("success_rate");
    any_mota = any_mota || row.values.count("mota");
    t.rows.push_back(std::move(row));
  }
  if (t.rows.empty()) {
    if (error) *error = "\"results\" has no rows";
    return BenchStatus::kNoResults;
  }
  if (!any_success && !any_mota) {
    if (error) *error = "rows carry neither \"success_rate\" (planning/nav) nor \"mota\" (perception)";
    return BenchStatus::kUnknownKind;
  }
  t.kind = any_success ? BenchKind::kPlanning : BenchKind::kPerception;
  const std::string key = any_success ? "success_rate" : "mota";
  std::vector<BenchRow> kept;
  for (auto& row : t.rows) {
    if (!row.values.count(key)) {
      ++t.skipped_rows;
      continue;
    }
    if (std::find(t.methods.begin(), t.methods.end(), row.method) == t.methods.end()) t.methods.push_back(row.method);
    kept.push_back(std::move(row));
  }
  t.rows = std::move(kept);
  *out = std::move(t);
  return BenchStatus::kOk;
}

BenchStatus loadBenchJson(const std::string& path, BenchTable* out, std::string* error) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    if (error) *error = path + ": cannot open";
    return BenchStatus::kOpenFailed;
  }
  std::stringstream ss;
  ss << f.rdbuf();
  const BenchStatus s = parseBenchJson(ss.str(), out, error);
  if (s != BenchStatus::kOk && error) *error = path + ": " + *error;
  return s;
}

std::vector<std::pair<int, std::vector<BenchBar>>> groupedBars(const BenchTable& t, const std::string& metric) {
  std::map<int, std::map<std::string, std::vector<double>>> acc;
  for (const auto& r : t.rows) {
    const auto it = r.values.find(metric);
    if (it == r.values.end()) continue;
    acc[r.n_dynamic][r.method].push_back(it->second);
  }
  std::vector<std::pair<int, std::vector<BenchBar>>> out;
  for (const auto& [nd, by_method] : acc) {
    std::vector<BenchBar> bars;
    for (const auto& m : t.methods) {
      const auto it = by_method.find(m);
      if (it == by_method.end()) continue;
      BenchBar b;
      b.method = m;
      b.n_dynamic = nd;
      b.count = static_cast<int>(it->second.size());
      b.min = *std::min_element(it->second.begin(), it->second.end());
      b.max = *std::max_element(it->second.begin(), it->second.end());
      double sum = 0.0;
      for (double v : it->second) sum += v;
      b.mean = sum / b.count;
      bars.push_back(b);
    }
    out.emplace_back(nd, std::move(bars));
  }
  return out;
}

}  // namespace plot
}  // namespace ucon
