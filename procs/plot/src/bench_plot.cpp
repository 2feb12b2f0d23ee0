#include "ucon/plot/bench_plot.hpp"

#include <algorithm>
#include <cmath>

#include "canvas.hpp"

namespace ucon {
namespace plot {

using detail::Align;
using detail::fmt;
using detail::setColour;
using detail::text;

namespace {

struct MetricInfo {
  const char* key;
  const char* label;
  double scale;       // value shown = value * scale
  bool fixed_0_100;   // percentage axis
};

const MetricInfo* info(const std::string& key) {
  static const MetricInfo kInfos[] = {
      {"success_rate", "success rate [%]", 100.0, true},
      {"plan_ms_median", "planning time, median [ms]", 1.0, false},
      {"time_to_goal_s", "time to goal [s]", 1.0, false},
      {"mota", "MOTA [%]", 100.0, true},
      {"idsw", "identity switches (IDSW)", 1.0, false},
  };
  for (const auto& i : kInfos) {
    if (key == i.key) return &i;
  }
  return nullptr;
}

bool anyHas(const BenchTable& t, const std::string& key) {
  return std::any_of(t.rows.begin(), t.rows.end(), [&](const BenchRow& r) { return r.values.count(key) > 0; });
}

void panel(cairo_t* cr, const BenchTable& t, const std::string& metric, double x0, double y0, double w, double h) {
  const MetricInfo* mi = info(metric);
  const auto groups = groupedBars(t, metric);
  double vmax = mi->fixed_0_100 ? 100.0 : 0.0;
  for (const auto& [nd, bars] : groups)
    for (const auto& b : bars) vmax = std::max(vmax, b.max * mi->scale);
  if (!mi->fixed_0_100) vmax = vmax > 0 ? niceLength(vmax) * std::ceil(vmax / niceLength(vmax) + 1e-9) : 1.0;
  const double px0 = x0 + 56, py0 = y0 + 34, pw = w - 70, ph = h - 34 - 52;
  setColour(cr, {0.1, 0.1, 0.1});
  text(cr, x0 + w / 2, y0 + 18, mi->label, 15, Align::kCentre, true);
  // Y axis with 5 ticks.
  cairo_set_line_width(cr, 1.0);
  for (int i = 0; i <= 5; ++i) {
    const double v = vmax * i / 5.0;
    const double y = py0 + ph - ph * i / 5.0;
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, px0, y);
    cairo_line_to(cr, px0 + pw, y);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    text(cr, px0 - 6, y + 4, fmt("%g", std::round(v * 100) / 100), 12, Align::kRight);
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_move_to(cr, px0, py0);
  cairo_line_to(cr, px0, py0 + ph);
  cairo_line_to(cr, px0 + pw, py0 + ph);
  cairo_stroke(cr);
  if (groups.empty()) return;
  const double gw = pw / groups.size();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const auto& [nd, bars] = groups[g];
    const double bw = std::min(70.0, 0.8 * gw / std::max<std::size_t>(1, bars.size()));
    const double gx = px0 + gw * g + (gw - bw * bars.size()) / 2.0;
    for (std::size_t i = 0; i < bars.size(); ++i) {
      const auto& b = bars[i];
      const auto mit = std::find(t.methods.begin(), t.methods.end(), b.method);
      const Rgb c = idColour(mit - t.methods.begin());
      const double v = b.mean * mi->scale;
      const double bh = ph * std::clamp(v / vmax, 0.0, 1.0);
      const double x = gx + bw * i;
      setColour(cr, c, 0.9);
      cairo_rectangle(cr, x + 2, py0 + ph - bh, bw - 4, bh);
      cairo_fill(cr);
      if (b.count > 1 && b.max > b.min) {  // min-max whisker over seeds
        const double ylo = py0 + ph - ph * std::clamp(b.min * mi->scale / vmax, 0.0, 1.0);
        const double yhi = py0 + ph - ph * std::clamp(b.max * mi->scale / vmax, 0.0, 1.0);
        cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
        cairo_set_line_width(cr, 1.2);
        cairo_move_to(cr, x + bw / 2, ylo);
        cairo_line_to(cr, x + bw / 2, yhi);
        cairo_move_to(cr, x + bw / 2 - 5, ylo);
        cairo_line_to(cr, x + bw / 2 + 5, ylo);
        cairo_move_to(cr, x + bw / 2 - 5, yhi);
        cairo_line_to(cr, x + bw / 2 + 5, yhi);
        cairo_stroke(cr);
      }
      // Value above the bar and its whisker.
      const double top = py0 + ph - ph * std::clamp(std::max(v, b.max * mi->scale) / vmax, 0.0, 1.0);
      cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
      text(cr, x + bw / 2, top - 5, fmt(std::abs(v) >= 100 ? "%.0f" : "%.3g", v), 11, Align::kCentre);
      if (nd < 0) text(cr, x + bw / 2, py0 + ph + 18, b.method, 12, Align::kCentre);  // no density: name the bar
    }
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    if (nd >= 0) text(cr, px0 + gw * (g + 0.5), py0 + ph + 18, fmt("N_d = %d", nd), 13, Align::kCentre);
    const int n = bars.empty() ? 0 : bars.front().count;
    if (n > 1) text(cr, px0 + gw * (g + 0.5), py0 + ph + 34, fmt("mean of %d runs", n), 11, Align::kCentre);
  }
}

}  // namespace

std::vector<std::string> benchMetrics(const BenchTable& t) {
  std::vector<std::string> out;
  if (t.kind == BenchKind::kPerception) {
    out.push_back("mota");
    if (anyHas(t, "idsw")) out.push_back("idsw");
    return out;
  }
  out.push_back("success_rate");
  if (anyHas(t, "plan_ms_median")) out.push_back("plan_ms_median");
  else if (anyHas(t, "time_to_goal_s")) out.push_back("time_to_goal_s");
  return out;
}

PlotStatus renderBenchPlot(const BenchTable& table, const BenchPlotOptions& opt, const std::string& path,
                           std::string* error) {
  if (table.rows.empty()) {
    if (error) *error = "no benchmark rows to chart";
    return PlotStatus::kNothingToDraw;
  }
  detail::Canvas canvas;
  if (!canvas.open(path, opt.width, opt.height, error)) return PlotStatus::kBadOptions;
  cairo_t* cr = canvas.cr();
  const double W = opt.width, H = opt.height;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, 24, 32, (opt.title.empty() ? std::string("benchmark") : opt.title) + "  —  " + toString(table.kind), 20,
       Align::kLeft, true);
  // Method legend across the top.
  double lx = 24;
  for (std::size_t i = 0; i < table.methods.size(); ++i) {
    setColour(cr, idColour(static_cast<int64_t>(i)), 0.9);
    cairo_rectangle(cr, lx, 46, 16, 16);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text(cr, lx + 22, 59, table.methods[i], 14);
    lx += 40 + detail::textWidth(cr, table.methods[i], 14);
  }
  const auto metrics = benchMetrics(table);
  const double pw = (W - 48) / metrics.size();
  for (std::size_t i = 0; i < metrics.size(); ++i) panel(cr, table, metrics[i], 24 + pw * i, 80, pw - 16, H - 96);
  if (!canvas.finish(error)) return PlotStatus::kWriteFailed;
  return PlotStatus::kOk;
}

}  // namespace plot
}  // namespace ucon
