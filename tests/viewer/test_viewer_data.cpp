// The playback page's data: frames at the requested rate, sectors and ellipses as ucon_plot
// computes them, the size budget lowering the rate, a self-contained page that no string in
// the data can break out of.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "../plot/synthetic_run.hpp"
#include "ucon/viewer/viewer_data.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace ucon::viewer;

namespace {
ucon::plot::RunData load(ucon_test::SyntheticRun gen = {}) {
  const auto p = fs::temp_directory_path() / ("ucon_view_" + std::to_string(getpid()) + ".lcm");
  EXPECT_TRUE(gen.write(p.string()));
  ucon::plot::RunData run;
  std::string err;
  EXPECT_EQ(ucon::plot::loadRunLog(p.string(), {}, &run, &err), ucon::plot::LoadStatus::kOk) << err;
  fs::remove(p);
  return run;
}
}  // namespace

TEST(ViewerJson, GivenTheSyntheticRunThenFramesAtTheRateWithRobotObjectsAndPlans) {
  const auto run = load();
  ViewerOptions opt;
  opt.title = "t";
  ViewerStats st;
  const json d = json::parse(buildViewerJson(run, opt, &st));
  EXPECT_EQ(d["version"], 1);
  EXPECT_EQ(d["scenario"], "synthetic");
  ASSERT_EQ(d["frames"].size(), 61u);  // 6 s at 10 Hz, both ends
  EXPECT_EQ(st.frames, 61);
  EXPECT_DOUBLE_EQ(st.rate_hz, 10.0);
  EXPECT_EQ(d["duration_ms"], 6000);

  // Frame 40 (t = 4.0 s): the robot where the synthetic run puts it, in cm; collision flag.
  const json& f = d["frames"][40];
  EXPECT_EQ(f["t"], 4000);
  ucon_test::SyntheticRun gen;
  double x, y, vx, vy;
  gen.robotAt(4.0, &x, &y, &vx, &vy);
  EXPECT_EQ(f["r"][0], std::llround(x * 100));
  EXPECT_EQ(f["r"][1], std::llround(y * 100));
  EXPECT_EQ(f["r"][3], std::llround(std::hypot(vx, vy) * 100));
  EXPECT_EQ(f["c"], 1);
  EXPECT_EQ(d["frames"][39]["c"], 0);
  ASSERT_EQ(d["collisions"].size(), 1u);
  EXPECT_EQ(d["collisions"][0][0], 4000);

  // Tracked objects: the latest frame before t (objects are at odd 20 ms ticks: 3.98 s).
  ASSERT_EQ(f["o"].size(), 3u);
  const json& o = f["o"][1];  // id 12: moves along -x at 1 m/s
  EXPECT_EQ(o[0], 12);
  EXPECT_EQ(o[3], -100);
  EXPECT_EQ(o[4], 0);
  // Its 2-sigma ellipse and sector, as ucon_plot computes them.
  Eigen::Matrix2d c;
  const double sx = 0.15, sy = 0.2;
  c << sx * sx, 0.5 * sx * sy, 0.5 * sx * sy, sy * sy;
  const auto e = ucon::plot::covarianceEllipse(c, 2.0);
  const auto s = ucon::plot::uncertaintySector({0, 0}, {-1, 0}, c, true, std::hypot(0.6, 0.6), {});
  ASSERT_TRUE(e && s);
  EXPECT_EQ(o[5], std::llround(e->a * 100));
  EXPECT_EQ(o[6], std::llround(e->b * 100));
  EXPECT_EQ(o[8], std::llround(s->radius * 100));
  EXPECT_EQ(o[9], std::llround(s->heading * 1000));  // pi: moving along -x
  EXPECT_EQ(o[10], std::llround(s->half_angle * 1000));
  ASSERT_EQ(f["g"].size(), 3u);
  EXPECT_EQ(f["g"][0][3], 30);  // radius 0.3 m

  // Plans: each frame points at the latest plan (every 0.2 s from 0.1 s), deduplicated.
  EXPECT_EQ(d["frames"][0]["p"], -1);
  EXPECT_GE(d["frames"][1]["p"], 0);
  EXPECT_EQ(d["plans"].size(), 30u);
  EXPECT_EQ(d["plans"][0]["pts"].size(), 2u * 21u);  // 2 s at 0.1 s = 21 points, under the cap
  // Static cells appear from the frame of their first hit.
  EXPECT_GT(d["static"]["cells"].size(), 300u);
  EXPECT_EQ(d["static"]["res"], 10);
}

TEST(ViewerJson, GivenASmallBudgetThenTheRateIsLoweredUntilItFits) {
  ucon_test::SyntheticRun gen;
  gen.duration_s = 20.0;
  const auto run = load(gen);
  ViewerOptions opt;
  opt.rate_hz = 50.0;
  ViewerStats big, small;
  const std::string a = buildViewerJson(run, opt, &big);
  opt.max_megabytes = 0.1;
  const std::string b = buildViewerJson(run, opt, &small);
  ASSERT_GT(a.size(), 100000u) << "the test needs a run larger than the budget";
  EXPECT_LE(b.size(), 100000u);
  EXPECT_LT(small.rate_hz, 50.0);
  EXPECT_EQ(small.json_bytes, b.size());
  EXPECT_LT(small.frames, big.frames);
  EXPECT_EQ(json::parse(b)["frames"].size(), static_cast<std::size_t>(small.frames));
}

TEST(ViewerJson, GivenAnEmptyRunThenNothing) {
  EXPECT_TRUE(buildViewerJson(ucon::plot::RunData{}, {}, nullptr).empty());
}

TEST(ViewerPage, GivenDataThenOneSelfContainedPageThatStringsCannotBreak) {
  auto run = load();
  run.scenario = "x</script><script>alert(1)</script><!--";
  ViewerOptions opt;
  const std::string js = buildViewerJson(run, opt, nullptr);
  const std::string page = renderViewerHtml(js, "a<b>&\"c\"");
  // Self-contained: nothing fetched, no external resource of any kind.
  for (const char* s : {"http:", "https:", "src=", "href=", "@import", "url(", "fetch(", "XMLHttpRequest"}) {
    EXPECT_EQ(page.find(s), std::string::npos) << s;
  }
  // Exactly the two script elements of the template: the data cannot close its element.
  std::size_t n = 0;
  for (auto p = page.find("</script>"); p != std::string::npos; p = page.find("</script>", p + 1)) ++n;
  EXPECT_EQ(n, 2u);
  EXPECT_EQ(page.find("alert(1)</script>"), std::string::npos);
  EXPECT_NE(page.find("<title>a&lt;b&gt;&amp;&quot;c&quot;</title>"), std::string::npos);
  EXPECT_NE(page.find("id=\"status\""), std::string::npos);
  // The embedded JSON reads back to the same document.
  const auto a = page.find("id=\"ucon-data\">") + std::string("id=\"ucon-data\">").size();
  const auto b = page.find("</script>", a);
  const json back = json::parse(page.substr(a, b - a));
  EXPECT_EQ(back, json::parse(js));
  EXPECT_EQ(back["scenario"], run.scenario);
}

TEST(ViewerJson, GivenABogusTimestampFarFromTheOthersThenTheFramesStayWithinTheBudget) {
  ucon::plot::RunData run;
  ucon::plot::PoseSample p;
  p.utime = 1'000'000;
  run.poses.push_back(p);
  p.utime = 1'000'000'000'000'000;  // ~31 years later
  p.x = 1.0;
  run.poses.push_back(p);
  ViewerOptions opt;
  opt.max_megabytes = 0.5;
  ViewerStats st;
  const std::string js = buildViewerJson(run, opt, &st);
  EXPECT_LE(js.size(), 500000u);
  EXPECT_LE(st.frames, 500000 / 40 + 1);
  EXPECT_GE(st.frames, 2);
  EXPECT_EQ(json::parse(js)["frames"].size(), static_cast<std::size_t>(st.frames));
}

namespace {
std::string runCmd(const std::string& cmd, int* rc) {
  std::string out;
  FILE* f = popen((cmd + " 2>&1").c_str(), "r");
  char buf[512];
  while (f && fgets(buf, sizeof(buf), f)) out += buf;
  const int st = f ? pclose(f) : -1;
  *rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return out;
}
}  // namespace

TEST(UconViewCli, GivenLogsThenAPageOrAClearErrorAndExitCode) {
  const std::string bin = UCON_BIN_DIR "/ucon-view";
  const auto dir = fs::temp_directory_path() / ("ucon_view_cli_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const auto log = dir / "run.lcm", page = dir / "run.html";
  ucon_test::SyntheticRun gen;
  ASSERT_TRUE(gen.write(log.string()));
  int rc = -1;
  std::string out = runCmd(bin + " " + log.string() + " -o " + page.string(), &rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("61 frames"), std::string::npos) << out;
  ASSERT_TRUE(fs::exists(page));
  EXPECT_GT(fs::file_size(page), 20000u);

  fs::remove(page);
  fs::resize_file(log, static_cast<uintmax_t>(gen.offsets.back() + 5));
  out = runCmd(bin + " " + log.string() + " -o " + page.string(), &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("byte offset " + std::to_string(gen.offsets.back())), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(page));

  {
    ucon::runtime::LogWriterFile w;
    std::string e;
    ASSERT_TRUE(w.open(log.string(), &e));
    const std::vector<uint8_t> d(8, 0);
    ASSERT_TRUE(w.write("LIDAR_IMU", d.data(), d.size(), 1));
  }
  out = runCmd(bin + " " + log.string() + " -o " + page.string(), &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("none of the channels"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(page));
  fs::remove_all(dir);
}
