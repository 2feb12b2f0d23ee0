// End-to-end check of the playback page in headless Chromium (Debian package `chromium`):
// ucon-view writes the page of a synthetic run; Chromium loads it with the network cut off;
// the page must report "frames: N, drawn" in its status element, log nothing on the console
// (no errors), its screenshot must show the run (not blank, collision mark and path
// colours present), and play/pause, speed and the slider must work. Exit 77 (ctest
// SKIP_RETURN_CODE) when Chromium is not installed.
#include <cairo.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "../plot/synthetic_run.hpp"

namespace fs = std::filesystem;

namespace {
constexpr int kSkip = 77;

std::string findChromium() {
  if (const char* env = std::getenv("UCON_CHROMIUM")) return env;
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    for (const char* name : {"chromium", "chromium-browser"}) {
      const fs::path p = fs::path(dir) / name;
      if (::access(p.c_str(), X_OK) == 0) return p.string();
    }
  }
  return {};
}

int sh(const std::string& cmd) {
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

int failures = 0;
void check(bool ok, const std::string& what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAIL", what.c_str());
  failures += ok ? 0 : 1;
}
}  // namespace

int main() {
  const std::string chromium = findChromium();
  if (chromium.empty()) {
    std::printf("SKIP: chromium is not installed (Debian package 'chromium'); the page test needs it\n");
    return kSkip;
  }
  char tmpl[] = "/tmp/ucon_view_chromium_XXXXXX";
  if (!::mkdtemp(tmpl)) {
    std::printf("FAIL: cannot create a temporary directory\n");
    return 1;
  }
  const fs::path dir(tmpl);
  const fs::path log = dir / "run.lcm", page = dir / "run.html", dom = dir / "dom.txt", err = dir / "stderr.txt",
                 shot = dir / "shot.png";
  ucon_test::SyntheticRun gen;
  check(gen.write(log.string()), "synthetic log written");
  check(sh(std::string(UCON_BIN_DIR) + "/ucon-view " + log.string() + " -o " + page.string() + " > /dev/null") == 0,
        "ucon-view wrote the page");

  // Chromium as root: no sandbox; nothing that reaches the network; a fresh profile.
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking"
      " --disable-component-update --disable-sync --disable-extensions --hide-scrollbars"
      " --host-resolver-rules='MAP * ~NOTFOUND' --window-size=1280,800 --virtual-time-budget=3000"
      " --enable-logging=stderr --v=0";
  const std::string url = "file://" + page.string();
  int rc = sh("timeout 90 " + chromium + flags + " --user-data-dir=" + (dir / "profile1").string() +
              " --dump-dom '" + url + "' > " + dom.string() + " 2> " + err.string());
  check(rc == 0, "chromium --dump-dom exit status " + std::to_string(rc));
  const std::string dom_text = slurp(dom);
  std::smatch m;
  const bool has_status =
      std::regex_search(dom_text, m, std::regex("<span id=\"status\">frames: (\\d+), drawn, ink pixels: (\\d+)</span>"));
  check(has_status, "status element says the page drew (" +
                        (has_status ? m.str(0) : std::string("status element not found or an error")) + ")");
  if (has_status) {
    check(std::stoi(m.str(1)) == 61, "61 frames (6 s at 10 Hz), page says " + m.str(1));
    check(std::stol(m.str(2)) > 5000, "the canvas has ink: " + m.str(2) + " pixels");
  }
  check(dom_text.find("class=\"error\"") == std::string::npos, "no error in the status element");
  // Console output of the page (errors, warnings, uncaught exceptions) is logged as
  // "...:CONSOLE...]": the page itself logs nothing, so any such line is a problem.
  std::stringstream es(slurp(err));
  std::string line;
  int console = 0;
  while (std::getline(es, line)) {
    if (line.find(":CONSOLE") != std::string::npos) {
      ++console;
      std::printf("  console: %s\n", line.c_str());
    }
  }
  check(console == 0, "no console messages");

  rc = sh("timeout 90 " + chromium + flags + " --user-data-dir=" + (dir / "profile2").string() +
          " --screenshot=" + shot.string() + " '" + url + "' > /dev/null 2>&1");
  check(rc == 0 && fs::exists(shot), "chromium --screenshot");
  cairo_surface_t* s = cairo_image_surface_create_from_png(shot.c_str());
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    cairo_surface_flush(s);
    const int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    const int stride = cairo_image_surface_get_stride(s) / 4;
    const auto* d = reinterpret_cast<const uint32_t*>(cairo_image_surface_get_data(s));
    long ink = 0, red = 0, yellow = 0, orange = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const uint32_t px = d[y * stride + x];
        const int r = (px >> 16) & 0xFF, g = (px >> 8) & 0xFF, b = px & 0xFF;
        ink += (r < 235 || g < 235 || b < 235) ? 1 : 0;
        red += (r > 190 && g < 50 && b < 50) ? 1 : 0;                 // collision mark #d90d0d
        yellow += (r > 200 && g > 200 && b < 90) ? 1 : 0;             // fast part of the path (viridis)
        orange += (r > 240 && g > 200 && g < 235 && b > 160 && b < 210) ? 1 : 0;  // sector fill
      }
    std::printf("screenshot %dx%d: ink %ld, red %ld, yellow %ld, sector %ld pixels\n", w, h, ink, red, yellow, orange);
    check(w == 1280 && h == 800, "screenshot size");
    check(ink > w * h / 50 && ink < w * h * 8 / 10, "screenshot is neither blank nor flooded");
    check(red > 30, "collision mark drawn");
    check(yellow > 100, "speed-coloured path drawn");
    check(orange > 150, "uncertainty sectors drawn");
  } else {
    check(false, "screenshot is a readable PNG");
  }
  cairo_surface_destroy(s);

  // Playback: a copy of the page with a script acting as the user: slider to the start, speed
  // 2x, play; 1.5 s later (browser virtual time) it should be ~3 s into the run and still
  // playing, and after the run's 6 s (3 s at 2x) stopped at the last frame.
  std::string html = slurp(page);
  const std::string user = R"(<script>
setTimeout(function () {
  var sl = document.getElementById("slider"); sl.value = "0"; sl.dispatchEvent(new Event("input"));
  document.getElementById("speed").value = "2"; document.getElementById("play").click(); }, 100);
function report(tag) { document.getElementById("status").textContent += " | " + tag + " " +
  document.getElementById("time").textContent + " btn " + document.getElementById("play").textContent; }
setTimeout(function () { report("at"); }, 1600);
setTimeout(function () { report("later"); }, 4500);
</script>
</body>)";
  const auto body = html.rfind("</body>");
  if (body != std::string::npos) html.replace(body, 7, user);
  const fs::path play = dir / "play.html", play_dom = dir / "play_dom.txt";
  {
    std::ofstream f(play, std::ios::binary);
    f << html;
  }
  rc = sh("timeout 90 " + chromium + flags + " --virtual-time-budget=6000 --user-data-dir=" +
          (dir / "profile3").string() + " --dump-dom 'file://" + play.string() + "' > " + play_dom.string() +
          " 2> /dev/null");
  const std::string pd = slurp(play_dom);
  std::smatch pm;
  const bool played = std::regex_search(
      pd, pm, std::regex(R"(\| at (\d+\.\d) / 6\.0 s +\[\d+/61\] btn (\S+) pause \| later 6\.0 / 6\.0 s +\[61/61\] btn (\S+) play)"));
  check(played, "playback reported (" + (played ? pm.str(0) : std::string("no report in the page")) + ")");
  if (played) {
    const double at = std::stod(pm.str(1));
    check(at >= 2.0 && at <= 4.0, "1.5 s at 2x played ~3 s of the run: " + pm.str(1) + " s");
  }

  if (failures == 0) fs::remove_all(dir);
  else std::printf("files kept in %s\n", dir.c_str());
  return failures == 0 ? 0 : 1;
}
