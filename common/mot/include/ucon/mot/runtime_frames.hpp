#pragma once
/// @file runtime_frames.hpp
/// CLEAR-MOT on the runtime's own messages: simulator ground truth (ucon::sim_ground_truth_t)
/// against perception output (ucon::tracked_objects_t), matched by x-y distance in metres.
/// Shared by `ucon-mot --log` and the perception benchmark so both count the same way.

#include <cstdint>
#include <vector>

#include "ucon/mot/clear_mot.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/tracked_objects_t.hpp"

namespace ucon {
namespace mot {

/// How ground truth and tracks are turned into CLEAR-MOT frames.
struct RuntimeEvalOptions {
  double threshold_m = 1.0;       ///< x-y match distance [m], > 0
  double max_time_gap_s = 0.05;   ///< ground truth farther in time from a frame is not used [s]
  double max_range_m = 0.0;       ///< ignore ground truth farther from the robot [m]; 0 = all
  bool include_tentative = false; ///< count tentative tracks as hypotheses
  bool exclude_coasting = false;  ///< do not count coasting tracks as hypotheses
};

/// Ground-truth objects at `utime` [us]: each object moved by its velocity over
/// (utime - gt.utime) so that a frame a few ms off still compares like with like; objects
/// farther than max_range_m from the robot are left out. Non-finite objects are skipped.
std::vector<PointXY> groundTruthAt(const sim_ground_truth_t& gt, int64_t utime,
                                   const RuntimeEvalOptions& opt);

/// Hypotheses of a perception message: confirmed (and, per options, coasting/tentative)
/// tracks with finite positions. An invalid message yields no hypotheses.
std::vector<PointXY> hypothesesOf(const tracked_objects_t& objects, const RuntimeEvalOptions& opt);

}  // namespace mot
}  // namespace ucon
