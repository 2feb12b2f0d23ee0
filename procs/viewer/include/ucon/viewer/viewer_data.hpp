#pragma once
/// @file viewer_data.hpp
/// The playback page of a run (ucon-view): the run resampled into frames at a fixed rate
/// (down-sampled until the page fits a size budget), as compact JSON embedded in one
/// self-contained HTML page (no network access: no CDN, no web fonts).

#include <cstdint>
#include <string>

#include "ucon/plot/geometry.hpp"
#include "ucon/plot/run_data.hpp"

namespace ucon {
namespace viewer {

struct ViewerOptions {
  double rate_hz = 10.0;          ///< frames per second of run time, 0.2..100
  double max_megabytes = 4.0;     ///< the rate is lowered until the JSON fits [MB], 0.1..500
  double sigma = 2.0;             ///< covariance ellipses at this many standard deviations
  int max_plan_points = 40;       ///< points kept per planned trajectory, 2..1000
  int min_static_hits = 2;        ///< static cells hit fewer times are noise, not shown
  double focus_margin = 15.0;     ///< tracked objects farther than this from the path/map/ground truth do not widen the initial view [m]
  double stale_s = 0.5;           ///< objects/ground truth older than this at a frame are not shown [s]
  plot::SectorParams sector;      ///< sector geometry (paper's defaults)
  std::string title;              ///< page title, e.g. the log's file name
};

/// What the page holds, for messages and tests.
struct ViewerStats {
  int frames = 0;
  double rate_hz = 0.0;      ///< rate used (may be below the requested one to fit the budget)
  int plans = 0;             ///< planned trajectories embedded
  int static_cells = 0;
  std::size_t json_bytes = 0;
};

/// The run as JSON (lengths in cm, angles in mrad, times in ms since the first message, as
/// integers; schema in viewer_data.cpp). Empty string when the run has nothing to show.
std::string buildViewerJson(const plot::RunData& run, const ViewerOptions& options, ViewerStats* stats);

/// One self-contained HTML page that plays `json` back. `title` is escaped.
std::string renderViewerHtml(const std::string& json, const std::string& title);

}  // namespace viewer
}  // namespace ucon
