#pragma once
/// @file bench_data.hpp
/// Benchmark results as written by tests/bench (JSON {"results": [...]}), reduced to the bars
/// ucon-plot --bench draws: success rate per method and obstacle density (planning and nav
/// benchmarks), MOTA and identity switches per method (perception benchmark).

#include <map>
#include <string>
#include <vector>

namespace ucon {
namespace plot {

enum class BenchKind {
  kPlanning,    ///< rows carry success_rate (and n_dynamic)
  kPerception,  ///< rows carry mota and idsw
};
const char* toString(BenchKind k);

/// One row of "results". Numbers that are null/NaN in the file are absent from `values`.
struct BenchRow {
  std::string method;   ///< "ucon" when the file has none (the nav benchmark runs one stack)
  int n_dynamic = -1;   ///< -1 = not given
  std::map<std::string, double> values;
};

struct BenchTable {
  BenchKind kind = BenchKind::kPlanning;
  std::vector<BenchRow> rows;
  std::vector<std::string> methods;  ///< in order of first appearance
  int skipped_rows = 0;              ///< rows that were not objects or lacked the metric
};

enum class BenchStatus { kOk, kOpenFailed, kParseError, kNoResults, kUnknownKind };
const char* toString(BenchStatus s);

/// Parses the JSON text. kParseError names the byte where parsing failed; kNoResults when
/// "results" is missing, not an array or has no usable row; kUnknownKind when rows carry
/// neither success_rate nor mota.
BenchStatus parseBenchJson(const std::string& text, BenchTable* out, std::string* error);
/// Reads and parses a file.
BenchStatus loadBenchJson(const std::string& path, BenchTable* out, std::string* error);

/// One bar: statistics of `metric` over the rows of one method (and density).
struct BenchBar {
  std::string method;
  int n_dynamic = -1;
  double mean = 0.0, min = 0.0, max = 0.0;
  int count = 0;  ///< rows averaged (seeds)
};

/// Bars of `metric` grouped by n_dynamic (ascending; one group of -1 when absent), one bar
/// per method present in the group (order of BenchTable::methods). Rows without the metric
/// are left out.
std::vector<std::pair<int, std::vector<BenchBar>>> groupedBars(const BenchTable& t, const std::string& metric);

}  // namespace plot
}  // namespace ucon
