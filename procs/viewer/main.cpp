// ucon-view: writes one self-contained HTML page that plays a run's LCM log back (map, robot,
// tracked objects with ids, sectors and covariance ellipses, the planned trajectory, a
// timeline with play/pause and speed). The page loads nothing from the network.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "ucon/viewer/viewer_data.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Write a self-contained HTML page that plays an LCM log of a run back."};
  std::string log, out;
  bool allow_truncated = false;
  ucon::viewer::ViewerOptions opt;
  ucon::plot::ExtractionParams ext;
  app.add_option("log", log, "LCM log of the run")->required();
  app.add_option("-o,--output", out, "output page (.html)")->required();
  app.add_option("--rate", opt.rate_hz, "frames per second of run time")->check(CLI::Range(0.2, 100.0));
  app.add_option("--max-mb", opt.max_megabytes, "lower the frame rate until the page fits [MB]")
      ->check(CLI::Range(0.1, 500.0));
  app.add_option("--sigma", opt.sigma, "covariance ellipses at this many standard deviations")
      ->check(CLI::Range(0.1, 10.0));
  app.add_option("--static-resolution", ext.static_resolution, "static point grid [m]")->check(CLI::Range(0.01, 10.0));
  app.add_flag("--allow-truncated", allow_truncated, "show what precedes damage in the log (still warns)");
  CLI11_PARSE(app, argc, argv);

  opt.title = std::filesystem::path(log).filename().string();
  ucon::plot::RunData run;
  std::string err;
  const auto st = ucon::plot::loadRunLog(log, ext, &run, &err);
  if (st == ucon::plot::LoadStatus::kCorrupt && allow_truncated && !run.empty()) {
    std::fprintf(stderr, "ucon-view: warning: %s; showing the %lld events before it\n", err.c_str(),
                 static_cast<long long>(run.events));
    opt.title += " (damaged)";
  } else if (st != ucon::plot::LoadStatus::kOk) {
    std::fprintf(stderr, "ucon-view: error: %s\n", err.c_str());
    return 2;
  }
  for (const auto& note : run.notes) std::fprintf(stderr, "%s: note: %s\n", "ucon-view", note.c_str());
  for (const auto& [k, n] : run.skipped)
    std::fprintf(stderr, "ucon-view: skipped %lld messages: %s\n", static_cast<long long>(n), k.c_str());

  ucon::viewer::ViewerStats stats;
  const std::string json = ucon::viewer::buildViewerJson(run, opt, &stats);
  if (json.empty()) {
    std::fprintf(stderr, "ucon-view: error: nothing to show in %s\n", log.c_str());
    return 2;
  }
  const std::string page = ucon::viewer::renderViewerHtml(json, opt.title);
  std::ofstream f(out, std::ios::binary | std::ios::trunc);
  f << page;
  f.close();
  if (!f) {
    std::fprintf(stderr, "ucon-view: error: cannot write %s\n", out.c_str());
    return 2;
  }
  std::printf("wrote %s: %d frames at %.3g Hz, %d plans, %d static cells, %.2f MB\n", out.c_str(), stats.frames,
              stats.rate_hz, stats.plans, stats.static_cells, page.size() / 1e6);
  return 0;
}
