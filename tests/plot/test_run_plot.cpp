// The run picture: PNG and SVG are written, the PNG shows the layers in their colours
// (speed-coloured path, collision mark, start marker, static points, legend panel); bad
// options and empty runs give clear errors. Also the ucon-plot command line end to end.
#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "synthetic_run.hpp"
#include "ucon/plot/run_plot.hpp"

namespace fs = std::filesystem;
using namespace ucon::plot;

namespace {
fs::path tmp(const std::string& name) {
  return fs::temp_directory_path() / ("ucon_plot_" + std::to_string(getpid()) + "_" + name);
}

RunData syntheticRun(const std::string& name, ucon_test::SyntheticRun gen = {}) {
  const auto p = tmp(name);
  EXPECT_TRUE(gen.write(p.string()));
  RunData run;
  std::string err;
  EXPECT_EQ(loadRunLog(p.string(), {}, &run, &err), LoadStatus::kOk) << err;
  fs::remove(p);
  return run;
}

// Counts the pixels of a PNG for which `pred(r, g, b)` holds (0..255).
struct Png {
  int width = 0, height = 0;
  int count(const std::function<bool(int, int, int)>& pred, int x0 = 0, int x1 = 1 << 30) const {
    int n = 0;
    for (int y = 0; y < height; ++y)
      for (int x = std::max(0, x0); x < std::min(width, x1); ++x) {
        const uint32_t px = data[static_cast<std::size_t>(y) * stride / 4 + x];
        if (pred((px >> 16) & 0xFF, (px >> 8) & 0xFF, px & 0xFF)) ++n;
      }
    return n;
  }
  std::vector<uint32_t> data;
  int stride = 0;
};
Png readPng(const fs::path& p) {
  Png out;
  cairo_surface_t* s = cairo_image_surface_create_from_png(p.c_str());
  EXPECT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    cairo_surface_flush(s);
    out.width = cairo_image_surface_get_width(s);
    out.height = cairo_image_surface_get_height(s);
    out.stride = cairo_image_surface_get_stride(s);
    const auto* d = reinterpret_cast<const uint32_t*>(cairo_image_surface_get_data(s));
    out.data.assign(d, d + static_cast<std::size_t>(out.stride) / 4 * out.height);
  }
  cairo_surface_destroy(s);
  return out;
}

std::string run(const std::string& cmd, int* rc) {
  std::string out;
  FILE* f = popen((cmd + " 2>&1").c_str(), "r");
  std::array<char, 512> buf{};
  while (f && fgets(buf.data(), buf.size(), f)) out += buf.data();
  const int st = f ? pclose(f) : -1;
  *rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return out;
}
}  // namespace

TEST(RunSummary, GivenTheSyntheticRunThenDistanceSpeedAndCountsAreRight) {
  const RunData r = syntheticRun("summary.lcm");
  const RunSummary s = summarise(r);
  EXPECT_NEAR(s.duration_s, 6.0, 1e-9);
  EXPECT_NEAR(s.distance_m, std::hypot(8.0, 2.0), 1e-3);  // straight line to the goal
  EXPECT_NEAR(s.max_speed, 1.5 * std::hypot(8.0, 2.0) / 6.0, 1e-3);  // smoothstep peak 1.5x mean
  EXPECT_NEAR(s.mean_speed, std::hypot(8.0, 2.0) / 6.0, 1e-3);
  EXPECT_EQ(s.collisions, 1);
  EXPECT_EQ(s.track_ids, 3);
  EXPECT_EQ(s.ground_truth_ids, 3);
  EXPECT_GT(s.static_cells, 100);
  EXPECT_DOUBLE_EQ(s.min_clearance, 0.0);
}

TEST(SnapshotTimes, GivenPlansThenSnapshotsAreSpreadOverThemAscending) {
  const RunData r = syntheticRun("snaps.lcm");
  const auto t = snapshotTimes(r, 4);
  ASSERT_EQ(t.size(), 4u);
  for (std::size_t i = 1; i < t.size(); ++i) EXPECT_GT(t[i], t[i - 1]);
  for (int64_t x : t) {
    const bool is_plan = std::any_of(r.trajectories.begin(), r.trajectories.end(),
                                     [&](const TrajectorySnapshot& s) { return s.utime == x; });
    EXPECT_TRUE(is_plan);
  }
  EXPECT_GT(t.front() - r.timeRange().first, 500'000);   // not the first plan
  EXPECT_LT(t.back(), r.timeRange().second);
  EXPECT_TRUE(snapshotTimes(r, 0).empty());
  EXPECT_TRUE(snapshotTimes(RunData{}, 4).empty());
}

TEST(RunPlot, GivenTheSyntheticRunThenThePngShowsEveryLayer) {
  const RunData run_data = syntheticRun("png.lcm");
  const auto out = tmp("run.png");
  RunPlotOptions opt;
  opt.title = "synthetic";
  std::string err;
  ASSERT_EQ(renderRunPlot(run_data, opt, out.string(), &err), PlotStatus::kOk) << err;
  const Png png = readPng(out);
  ASSERT_EQ(png.width, 1600);
  ASSERT_EQ(png.height, 1100);
  const int plot_x1 = 1600 - 340;  // legend panel on the right
  const int total = png.width * png.height;
  const int white = png.count([](int r, int g, int b) { return r > 250 && g > 250 && b > 250; });
  EXPECT_LT(white, total * 97 / 100);  // not blank
  EXPECT_GT(white, total / 2);         // not a flood either
  // Collision mark (0.85, 0.05, 0.05) in the map.
  EXPECT_GT(png.count([](int r, int g, int b) { return r > 200 && g < 30 && b < 30; }, 0, plot_x1), 50);
  // Start marker green (0.10, 0.65, 0.20).
  EXPECT_GT(png.count([](int r, int g, int b) { return r < 40 && g > 150 && g < 180 && b < 60; }, 0, plot_x1), 50);
  // The path is coloured by speed: many of the 64 speed colours appear, the fastest
  // included (the slowest are under the start marker and the first snapshot).
  int bins = 0;
  bool fastest = false;
  for (int k = 0; k < 64; ++k) {
    const Rgb c = speedColour(k / 63.0);
    const int cr = static_cast<int>(std::lround(c.r * 255)), cg = static_cast<int>(std::lround(c.g * 255)),
              cb = static_cast<int>(std::lround(c.b * 255));
    const int n = png.count(
        [&](int r, int g, int b) { return std::abs(r - cr) <= 1 && std::abs(g - cg) <= 1 && std::abs(b - cb) <= 1; },
        0, plot_x1);
    bins += n >= 5 ? 1 : 0;
    fastest = fastest || (k >= 61 && n >= 20);
  }
  EXPECT_GE(bins, 15);
  EXPECT_TRUE(fastest);
  // Static points dark grey (0.30).
  EXPECT_GT(png.count([](int r, int g, int b) { return r == g && g == b && r > 70 && r < 85; }, 0, plot_x1), 500);
  // Planned trajectory magenta (0.84, 0.16, 0.62).
  EXPECT_GT(png.count([](int r, int g, int b) { return r > 200 && g < 60 && b > 140 && b < 170; }, 0, plot_x1), 50);
  // Legend panel background (0.97) exists on the right.
  EXPECT_GT(png.count([](int r, int g, int b) { return r >= 246 && r <= 248 && r == g && g == b; }, plot_x1), 10000);
  fs::remove(out);
}

TEST(RunPlot, GivenAnSvgNameThenAnSvgDocumentIsWritten) {
  const RunData r = syntheticRun("svg.lcm");
  const auto out = tmp("run.svg");
  std::string err;
  ASSERT_EQ(renderRunPlot(r, {}, out.string(), &err), PlotStatus::kOk) << err;
  std::ifstream f(out);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string svg = ss.str();
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("rgb(85%,5%,5%)"), std::string::npos);  // the collision mark's red
  fs::remove(out);
}

TEST(RunPlot, GivenBadOptionsOrNothingToDrawThenClearErrors) {
  const RunData r = syntheticRun("bad.lcm");
  std::string err;
  EXPECT_EQ(renderRunPlot(r, {}, tmp("run.jpg").string(), &err), PlotStatus::kBadOptions);
  EXPECT_NE(err.find(".png or .svg"), std::string::npos) << err;
  RunPlotOptions opt;
  opt.width = 10;
  EXPECT_EQ(renderRunPlot(r, opt, tmp("x.png").string(), &err), PlotStatus::kBadOptions);
  EXPECT_NE(err.find("size"), std::string::npos) << err;
  EXPECT_EQ(renderRunPlot(RunData{}, {}, tmp("x.png").string(), &err), PlotStatus::kNothingToDraw);
  EXPECT_EQ(renderRunPlot(r, {}, "/nonexistent-dir/x.png", &err), PlotStatus::kWriteFailed);
  EXPECT_NE(err.find("/nonexistent-dir/x.png"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(tmp("x.png")));
}

TEST(UconPlotCli, GivenLogsThenPictureOrAClearErrorAndExitCode) {
  const std::string bin = UCON_BIN_DIR "/ucon-plot";
  const auto log = tmp("cli.lcm");
  ucon_test::SyntheticRun gen;
  ASSERT_TRUE(gen.write(log.string()));
  const auto png = tmp("cli.png");
  int rc = -1;
  std::string out = run(bin + " " + log.string() + " -o " + png.string(), &rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("wrote"), std::string::npos) << out;
  EXPECT_GT(fs::file_size(png), 20000u);

  // Truncated: error with the byte offset of the damaged event, exit 2, no picture.
  fs::remove(png);
  fs::resize_file(log, static_cast<uintmax_t>(gen.offsets.back() + 10));
  out = run(bin + " " + log.string() + " -o " + png.string(), &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("byte offset " + std::to_string(gen.offsets.back())), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(png));
  // ... unless asked to draw what precedes the damage.
  out = run(bin + " --allow-truncated " + log.string() + " -o " + png.string(), &rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("warning"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(png));

  // A log with none of the channels.
  ucon_test::SyntheticRun none;
  none.pose = none.ground_truth = none.objects = none.static_points = none.trajectory = false;
  ASSERT_TRUE(none.write(log.string()));
  out = run(bin + " " + log.string() + " -o " + png.string(), &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("none of the channels"), std::string::npos) << out;

  // Missing file, garbage file.
  out = run(bin + " /nonexistent.lcm -o " + png.string(), &rc);
  EXPECT_EQ(rc, 2) << out;
  {
    std::ofstream f(log, std::ios::binary | std::ios::trunc);
    f << "this is not an LCM log at all, just text";
  }
  out = run(bin + " " + log.string() + " -o " + png.string(), &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("byte offset 0"), std::string::npos) << out;
  fs::remove(log);
  fs::remove(png);
}
