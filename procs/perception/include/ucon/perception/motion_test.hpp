#pragma once
/// @file motion_test.hpp
/// The FAPP-style motion test: which points of a frame are new surface, not seen in the frames
/// 0.5-1.0 s old, and not explained away by the robot's own motion (disocclusion).
///
/// The reference history merges consecutive frames into chunks of ~history_chunk seconds, each
/// indexed once when it closes (a few grid queries per point instead of one per frame; the test
/// only asks whether any reference point lies near, see ProximityIndex). Each chunk also keeps
/// the farthest and the nearest return per direction seen from its sensor origin: the space at
/// a point was free where a return of its bin lay beyond it and none clearly in front of it.
/// A point the reference cannot judge (another mover stood in front of it through the whole
/// window) is asked of a longer memory of where the sensor saw through (free_space_memory.hpp).

#include <cstdint>
#include <deque>
#include <vector>

#include <Eigen/Core>

#include "ucon/perception/angular_grid.hpp"
#include "ucon/perception/free_space_memory.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/preprocess.hpp"
#include "ucon/perception/proximity_index.hpp"

namespace ucon {
namespace perception {

/// What the test found for the points of one cluster (for diagnostics: why a cluster is not
/// moving). Each tested point counts once.
struct MotionEvidence {
  int near_reference = 0;  ///< a reference point lies near: not new surface
  int moved = 0;           ///< new surface where the reference saw free space: motion
  int surface = 0;         ///< new surface where the reference saw a surface at its range (or around it)
  int undecided = 0;       ///< new surface the reference could not judge: every return in its
                           ///< direction lay well in front of it (an occluder), or the bin was mixed
  int remembered = 0;      ///< new surface the reference could not judge and the free-space memory
                           ///< saw free a moment before: motion (counted in `moved` too)
};

class MotionTest {
 public:
  /// `grid`: bins of the free-space evidence (segmentation.free_space_bin_deg).
  MotionTest(const SegmentationParams& params, const AngularGrid& grid);

  /// Chooses the reference chunks for a frame at `utime` [us]: the closed chunks between
  /// history_min_age and history_max_age old; none while they cover less than 60 % of that
  /// window (a partial window is too sparse: start-up).
  void selectReference(int64_t utime);
  /// Whether the test can run on this frame (selectReference found a reference).
  bool hasReference() const { return !ref_chunks_.empty(); }

  /// Tests the points `indices` of `frame` (a cluster whose box is centred at `center`): a
  /// point with no reference point within motion_distance (+ motion_distance_per_m per metre
  /// of the cluster's range) that passes the free-space check has moved and is marked 1 in
  /// `moved` (indexed like frame.points). Returns how many moved; `evidence` (optional) gets
  /// what was found per point.
  int markMoved(const Frame& frame, const std::vector<int>& indices, const Eigen::Vector2d& center,
                std::vector<char>* moved, MotionEvidence* evidence = nullptr) const;

  /// Adds a processed frame to the history: its returns as free-space evidence (of the
  /// reference and of the longer memory), and as reference points those it did not give to
  /// tracks (`tracked_point`, per frame point) when history_static_only. Forgets the reference
  /// chosen for this frame.
  void push(const Frame& frame, const std::vector<char>& tracked_point);

 private:
  struct HistoryChunk {
    int64_t first_utime = 0;
    int64_t last_utime = 0;
    Points points;
    ProximityIndex index;
    bool closed = false;
    Eigen::Vector3f origin = Eigen::Vector3f::Zero();  ///< sensor origin of its first frame [m]
    std::vector<float> max_range;  ///< farthest return per angular bin seen from origin [m]; 0 = none
    std::vector<float> min_range;  ///< nearest return per angular bin seen from origin [m]; inf = none
  };
  enum class Verdict { kMoved, kSurface, kUndecided };
  Verdict pointMoved(const Frame& frame, const Eigen::Vector3f& p) const;
  bool unseenMoved(const Eigen::Vector3f& p) const;

  SegmentationParams params_;
  AngularGrid grid_;
  FreeSpaceMemory memory_;
  std::deque<HistoryChunk> history_;
  std::vector<const HistoryChunk*> ref_chunks_;  ///< the reference of the current frame
};

}  // namespace perception
}  // namespace ucon
