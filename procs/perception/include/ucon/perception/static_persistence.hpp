#pragma once
/// @file static_persistence.hpp
/// Which x-y cells have been occupied long enough to count as static structure.
///
/// A moving object that the motion test missed leaves its points in PERCEPTION_STATIC, and
/// the planner's map turns them into ghost obstacles along its path. Structure stays where
/// it is: a point goes to the static output only once its x-y cell has been hit without a
/// long gap for `persistence` seconds. Fast movers never hold a cell that long; newly seen
/// structure is published `persistence` later. Time comes from frame stamps only.
///
/// A cell hidden behind something nearer (a crowd walking in front of a box) is not seen, which
/// is no evidence that it emptied: with an occlusion view, such a cell keeps its run through
/// the gap, so the box counts as old structure when it is seen again. Not a cell whose last hit
/// a track took (a tracked person hidden while standing may walk off behind the occluder), and
/// only for Occlusion::max_hidden after that hit (a place hidden for long is unknown).

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ucon/cell_age.hpp"
#include "ucon/perception/angular_grid.hpp"

namespace ucon {
namespace perception {

class StaticPersistence {
 public:
  /// What a frame saw nearest in each direction: a cell whose last hit lies more than `margin`
  /// behind the nearest return in its bin (seen from `origin`) is hidden this frame.
  struct Occlusion {
    Eigen::Vector3f origin = Eigen::Vector3f::Zero();  ///< sensor origin, world [m]
    const AngularGrid* grid = nullptr;                 ///< the bins of `nearest`
    const std::vector<float>* nearest = nullptr;       ///< nearest return per bin [m]; inf = none
    float margin = 0.3f;                               ///< [m]
    /// Cells farther than this from `origin` (x-y) are not held: the frames' points stop there,
    /// so such a cell is neither seen nor asked about, and it ends after max_gap instead of
    /// staying in the list (a long drive would otherwise gather every cell it left behind) [m].
    float max_range = 15.0f;
    /// A cell is held only this long after its last hit: a place hidden for long (behind a
    /// pillar) is unknown, not occupied [s].
    double max_hidden = 3.0;
  };

  /// @param cell x-y cell edge [m], > 0
  /// @param persistence a cell must have been occupied this long [s], >= 0 (0: every point passes)
  /// @param max_gap a cell not hit for longer than this starts over [s], > 0
  /// @param cells_per_side the rolling grid's side in cells (a power of two; it must span the
  ///        sensor's range twice over: 256 cells of 0.2 m cover +-25 m)
  StaticPersistence(double cell, double persistence, double max_gap, int cells_per_side = 256);

  /// Records the x-y cells of `points` as hit at `utime` and marks in `persistent` (resized to
  /// points.size()) the points whose cell has been occupied for at least `persistence`.
  /// Frames must come in non-decreasing time; an earlier stamp resets the grid.
  /// With `occlusion`, every occupied cell this frame did not hit but hid keeps its run, unless
  /// all the points of its last hit were marked in `tracked` (same size as `points`, or null:
  /// none tracked).
  void update(int64_t utime, const std::vector<Eigen::Vector3f>& points, std::vector<char>* persistent,
              const Occlusion* occlusion = nullptr, const std::vector<char>* tracked = nullptr);

  /// Since when the cell holding (x, y) [m] has been occupied without a gap, as of the frames
  /// recorded so far [us]; CellAge::kNever when it is not occupied at `now` [us].
  int64_t occupiedSince(double x, double y, int64_t now) const { return cells_.occupiedSince(x, y, now); }

  void reset();

  /// Cells whose run was carried through a frame by occlusion so far (a counter for the status).
  int64_t holds() const { return holds_; }

 private:
  /// An occupied cell and the point that last hit it (where the occlusion test looks).
  struct Live {
    int slot;
    int64_t key;
    Eigen::Vector3f point;
    int64_t hit_utime;  ///< time of that hit [us]
    bool tracked;       ///< every point of that hit belonged to a track
  };
  void holdHidden(int64_t utime, const Occlusion& occlusion);
  CellAge cells_;
  int64_t persistence_us_;
  int64_t last_utime_ = INT64_MIN;
  std::vector<int> point_slot_;
  std::vector<Live> live_;        ///< the cells with a current run (kept only with an occlusion view)
  std::vector<int> live_index_;   ///< per slot: its entry in live_, -1 = none
  int64_t holds_ = 0;
};

}  // namespace perception
}  // namespace ucon
