// Benchmark JSON: the planning/nav and perception layouts of tests/bench, nulls for NaN,
// bad files with clear errors; the chart is written and not blank.
#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "ucon/plot/bench_plot.hpp"

namespace fs = std::filesystem;
using namespace ucon::plot;

namespace {
const char* kPlanning = R"({"world": {"num_static": 160}, "results": [
  {"method": "sector", "n_dynamic": 50, "runs": 2, "success_rate": 1.0, "plan_ms_median": 2.5},
  {"method": "fapp", "n_dynamic": 50, "runs": 2, "success_rate": 0.5, "plan_ms_median": 1.5},
  {"method": "sector", "n_dynamic": 80, "runs": 2, "success_rate": 0.9, "plan_ms_median": null},
  {"method": "fapp", "n_dynamic": 80, "runs": 2, "success_rate": null},
  {"method": "no_uncertainty", "n_dynamic": 80, "runs": 2, "success_rate": 0.7, "plan_ms_median": 2.0}
]})";
const char* kPerception = R"({"scenario": "pedestrians", "results": [
  {"method": "ucon", "seed": 1, "mota": 0.90, "idsw": 2},
  {"method": "ucon", "seed": 2, "mota": 0.96, "idsw": 0},
  {"method": "fapp", "seed": 1, "mota": 0.70, "idsw": 9},
  {"method": "fapp", "seed": 2, "mota": 0.80, "idsw": 7}
]})";
}  // namespace

TEST(BenchData, GivenPlanningResultsThenBarsPerDensityAndMethodSkipNulls) {
  BenchTable t;
  std::string err;
  ASSERT_EQ(parseBenchJson(kPlanning, &t, &err), BenchStatus::kOk) << err;
  EXPECT_EQ(t.kind, BenchKind::kPlanning);
  EXPECT_EQ(t.methods, (std::vector<std::string>{"sector", "fapp", "no_uncertainty"}));
  EXPECT_EQ(t.rows.size(), 4u);  // fapp@80 has a null success rate
  EXPECT_EQ(t.skipped_rows, 1);
  const auto g = groupedBars(t, "success_rate");
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0].first, 50);
  ASSERT_EQ(g[0].second.size(), 2u);
  EXPECT_EQ(g[0].second[1].method, "fapp");
  EXPECT_DOUBLE_EQ(g[0].second[1].mean, 0.5);
  EXPECT_EQ(g[1].first, 80);
  ASSERT_EQ(g[1].second.size(), 2u);
  EXPECT_EQ(g[1].second[1].method, "no_uncertainty");
  EXPECT_EQ(benchMetrics(t), (std::vector<std::string>{"success_rate", "plan_ms_median"}));
  EXPECT_EQ(groupedBars(t, "plan_ms_median")[1].second.size(), 1u);  // the null is left out
}

TEST(BenchData, GivenPerceptionResultsThenMeanMinMaxOverSeedsPerMethod) {
  BenchTable t;
  std::string err;
  ASSERT_EQ(parseBenchJson(kPerception, &t, &err), BenchStatus::kOk) << err;
  EXPECT_EQ(t.kind, BenchKind::kPerception);
  EXPECT_EQ(benchMetrics(t), (std::vector<std::string>{"mota", "idsw"}));
  const auto g = groupedBars(t, "idsw");
  ASSERT_EQ(g.size(), 1u);
  EXPECT_EQ(g[0].first, -1);
  ASSERT_EQ(g[0].second.size(), 2u);
  EXPECT_EQ(g[0].second[0].method, "ucon");
  EXPECT_DOUBLE_EQ(g[0].second[0].mean, 1.0);
  EXPECT_DOUBLE_EQ(g[0].second[1].min, 7.0);
  EXPECT_DOUBLE_EQ(g[0].second[1].max, 9.0);
  EXPECT_EQ(g[0].second[1].count, 2);
  const auto m = groupedBars(t, "mota");
  EXPECT_NEAR(m[0].second[0].mean, 0.93, 1e-12);
}

TEST(BenchData, GivenTheNavLayoutWithoutMethodThenOneMethodNamedUcon) {
  BenchTable t;
  std::string err;
  ASSERT_EQ(parseBenchJson(R"({"results": [{"n_dynamic": 50, "runs": 3, "success_rate": 1, "time_to_goal_s": 40},
                                          {"n_dynamic": 80, "runs": 3, "success_rate": 0.67, "time_to_goal_s": 45}]})",
                           &t, &err),
            BenchStatus::kOk);
  EXPECT_EQ(t.methods, (std::vector<std::string>{"ucon"}));
  EXPECT_EQ(benchMetrics(t), (std::vector<std::string>{"success_rate", "time_to_goal_s"}));
}

TEST(BenchData, GivenBadFilesThenClearErrors) {
  BenchTable t;
  std::string err;
  EXPECT_EQ(parseBenchJson(R"({"results": [ {"method": "x", )", &t, &err), BenchStatus::kParseError);
  EXPECT_NE(err.find("byte"), std::string::npos) << err;
  EXPECT_EQ(parseBenchJson(R"({"rows": []})", &t, &err), BenchStatus::kNoResults);
  EXPECT_EQ(parseBenchJson(R"({"results": []})", &t, &err), BenchStatus::kNoResults);
  EXPECT_EQ(parseBenchJson(R"({"results": [1, "a", {"method": "m", "energy": 3}]})", &t, &err),
            BenchStatus::kUnknownKind);
  EXPECT_NE(err.find("success_rate"), std::string::npos) << err;
  EXPECT_EQ(loadBenchJson("/nonexistent.json", &t, &err), BenchStatus::kOpenFailed);
  EXPECT_NE(err.find("/nonexistent.json"), std::string::npos);
}

TEST(BenchPlot, GivenBothKindsThenChartsAreWrittenWithBarsInTheMethodColours) {
  for (const char* json : {kPlanning, kPerception}) {
    BenchTable t;
    std::string err;
    ASSERT_EQ(parseBenchJson(json, &t, &err), BenchStatus::kOk);
    const auto out = fs::temp_directory_path() / ("ucon_bench_" + std::to_string(getpid()) + ".png");
    ASSERT_EQ(renderBenchPlot(t, {}, out.string(), &err), PlotStatus::kOk) << err;
    cairo_surface_t* s = cairo_image_surface_create_from_png(out.c_str());
    ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
    EXPECT_EQ(cairo_image_surface_get_width(s), 1400);
    // Method 0's colour (0.122, 0.467, 0.706) at alpha 0.9 on white: bars are there.
    const auto* d = reinterpret_cast<const uint32_t*>(cairo_image_surface_get_data(s));
    const int n = cairo_image_surface_get_stride(s) / 4 * cairo_image_surface_get_height(s);
    int blue = 0;
    for (int i = 0; i < n; ++i) {
      const int r = (d[i] >> 16) & 0xFF, g = (d[i] >> 8) & 0xFF, b = d[i] & 0xFF;
      blue += (r > 40 && r < 70 && g > 115 && g < 140 && b > 175 && b < 200) ? 1 : 0;
    }
    EXPECT_GT(blue, 2000);
    cairo_surface_destroy(s);
    fs::remove(out);
  }
}
