// ucon-plot: a bird's-eye picture of a run from its LCM log (PNG or SVG), or a chart of a
// benchmark's JSON results (--bench).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>

#include "ucon/plot/bench_plot.hpp"
#include "ucon/plot/run_plot.hpp"

namespace {
int plotBench(const std::string& json, const std::string& out, int width, int height) {
  ucon::plot::BenchTable table;
  std::string err;
  if (ucon::plot::loadBenchJson(json, &table, &err) != ucon::plot::BenchStatus::kOk) {
    std::fprintf(stderr, "ucon-plot: error: %s\n", err.c_str());
    return 2;
  }
  ucon::plot::BenchPlotOptions opt;
  opt.width = width > 0 ? width : opt.width;
  opt.height = height > 0 ? height : opt.height;
  opt.title = std::filesystem::path(json).filename().string();
  if (ucon::plot::renderBenchPlot(table, opt, out, &err) != ucon::plot::PlotStatus::kOk) {
    std::fprintf(stderr, "ucon-plot: error: %s\n", err.c_str());
    return 2;
  }
  std::printf("wrote %s (%s benchmark, %zu rows, %zu methods%s)\n", out.c_str(), toString(table.kind),
              table.rows.size(), table.methods.size(),
              table.skipped_rows ? (", " + std::to_string(table.skipped_rows) + " rows skipped").c_str() : "");
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Draw a run from its LCM log (PNG/SVG), or chart a benchmark's JSON (--bench)."};
  std::string log, out, bench;
  int width = 0, height = 0;
  bool allow_truncated = false;
  ucon::plot::RunPlotOptions opt;
  ucon::plot::ExtractionParams ext;
  app.add_option("log", log, "LCM log of the run");
  app.add_option("-o,--output", out, "output picture, .png or .svg")->required();
  app.add_option("--bench", bench, "chart this benchmark JSON instead of a log");
  app.add_option("--width", width, "picture width [px]");
  app.add_option("--height", height, "picture height [px]");
  app.add_option("--snapshots", opt.snapshots, "snapshots of sectors and plans")->check(CLI::Range(0, 20));
  app.add_option("--sigma", opt.sigma, "covariance ellipses at this many standard deviations")
      ->check(CLI::Range(0.1, 10.0));
  app.add_option("--static-resolution", ext.static_resolution, "static point grid [m]")->check(CLI::Range(0.01, 10.0));
  app.add_flag("--allow-truncated", allow_truncated, "draw what precedes damage in the log (still warns)");
  CLI11_PARSE(app, argc, argv);

  if (!bench.empty()) {
    if (!log.empty()) {
      std::fprintf(stderr, "ucon-plot: error: give either a log or --bench, not both\n");
      return 2;
    }
    return plotBench(bench, out, width, height);
  }
  if (log.empty()) {
    std::fprintf(stderr, "ucon-plot: error: a log file (or --bench JSON) is required\n");
    return 2;
  }
  if (width > 0) opt.width = width;
  if (height > 0) opt.height = height;
  opt.title = std::filesystem::path(log).filename().string();

  ucon::plot::RunData run;
  std::string err;
  const auto st = ucon::plot::loadRunLog(log, ext, &run, &err);
  if (st == ucon::plot::LoadStatus::kCorrupt && allow_truncated && !run.empty()) {
    std::fprintf(stderr, "ucon-plot: warning: %s; drawing the %lld events before it\n", err.c_str(),
                 static_cast<long long>(run.events));
    opt.title += " (damaged)";
  } else if (st != ucon::plot::LoadStatus::kOk) {
    std::fprintf(stderr, "ucon-plot: error: %s\n", err.c_str());
    return 2;
  }
  for (const auto& note : run.notes) std::fprintf(stderr, "%s: note: %s\n", "ucon-plot", note.c_str());
  for (const auto& [k, n] : run.skipped)
    std::fprintf(stderr, "ucon-plot: skipped %lld messages: %s\n", static_cast<long long>(n), k.c_str());
  if (ucon::plot::renderRunPlot(run, opt, out, &err) != ucon::plot::PlotStatus::kOk) {
    std::fprintf(stderr, "ucon-plot: error: %s\n", err.c_str());
    return 2;
  }
  const auto s = ucon::plot::summarise(run);
  std::printf("wrote %s: %.1f s, path %.1f m, %d tracked ids, %d collisions\n", out.c_str(), s.duration_s,
              s.distance_m, s.track_ids, s.collisions);
  return 0;
}
