#pragma once
/// @file bench_plot.hpp
/// Chart of a benchmark's results (PNG or SVG): planning/nav benchmarks get success rate per
/// method grouped by obstacle density (plus planning time or time to goal when present);
/// the perception benchmark gets MOTA and identity switches per method (mean over seeds,
/// whiskers from min to max).

#include <string>

#include "ucon/plot/bench_data.hpp"
#include "ucon/plot/run_plot.hpp"

namespace ucon {
namespace plot {

struct BenchPlotOptions {
  int width = 1400;   ///< [px], 200..20000
  int height = 700;   ///< [px], 150..20000
  std::string title;  ///< e.g. the JSON file name
};

/// The metrics charted for a table, in panel order, e.g. {"success_rate", "plan_ms_median"}.
std::vector<std::string> benchMetrics(const BenchTable& t);

PlotStatus renderBenchPlot(const BenchTable& table, const BenchPlotOptions& options, const std::string& path,
                           std::string* error);

}  // namespace plot
}  // namespace ucon
