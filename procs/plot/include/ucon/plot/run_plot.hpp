#pragma once
/// @file run_plot.hpp
/// The bird's-eye picture of a run (PNG or SVG, by the file's extension), drawn with cairo:
/// static points, the robot's path coloured by speed, moving obstacles' ground-truth tracks,
/// tracked objects' tracks with their ids, a few snapshots (planned trajectory, uncertainty
/// sectors, 2-sigma covariance ellipses, velocity arrows), collisions, legend and scale bar.

#include <cstdint>
#include <string>
#include <vector>

#include "ucon/plot/geometry.hpp"
#include "ucon/plot/run_data.hpp"

namespace ucon {
namespace plot {

struct RunPlotOptions {
  int width = 1600;             ///< picture width [px] (SVG: pt), 200..20000
  int height = 1100;            ///< picture height [px], 150..20000
  int snapshots = 4;            ///< snapshots of sectors and plans, 0..20
  double sigma = 2.0;           ///< covariance ellipse drawn at this many standard deviations
  int min_static_hits = 2;      ///< static cells hit fewer times are noise, not drawn
  double focus_margin = 15.0;   ///< tracked objects farther than this from the path/map/ground truth do not widen the view [m]
  SectorParams sector;          ///< sector geometry (paper's defaults)
  std::string title;            ///< first line of the title, e.g. the log's file name
};

/// Figures of a run, for the title block and for tests.
struct RunSummary {
  double duration_s = 0.0;     ///< first to last extracted message [s]
  double distance_m = 0.0;     ///< length of the robot path [m]
  double mean_speed = 0.0;     ///< distance / path duration [m/s]
  double max_speed = 0.0;      ///< [m/s]
  int collisions = 0;          ///< collision episodes (ground truth)
  double min_clearance = -1.0; ///< from the last ground truth [m]; -1 = unknown
  int track_ids = 0;           ///< distinct tracked-object ids
  int ground_truth_ids = 0;    ///< distinct simulated moving obstacles
  int static_cells = 0;        ///< static cells drawn
};
RunSummary summarise(const RunData& run, int min_static_hits = 2);

/// Times of the `n` snapshots [us]: evenly spread over the planned trajectories when there
/// are any, else over the run. Ascending; empty for an empty run or n <= 0.
std::vector<int64_t> snapshotTimes(const RunData& run, int n);

enum class PlotStatus { kOk, kBadOptions, kNothingToDraw, kWriteFailed };
const char* toString(PlotStatus s);

/// Draws the run into `path` (.png or .svg).
PlotStatus renderRunPlot(const RunData& run, const RunPlotOptions& options, const std::string& path,
                         std::string* error);

}  // namespace plot
}  // namespace ucon
