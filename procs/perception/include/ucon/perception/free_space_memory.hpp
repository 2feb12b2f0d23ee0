#pragma once
/// @file free_space_memory.hpp
/// Where the sensor has seen through the space people occupy, and when: the x-y cells that a
/// ray crossed low (between two heights above the floor) in the last few seconds.
///
/// The motion test compares a frame with a reference 0.5-1.0 s old. In a crowd another mover
/// often stood in front of a point through that whole window, so the reference cannot tell
/// whether the point's place was free (MotionTest's "undecided"). This memory looks further
/// back: a cell that a ray crossed at the height of a person's legs a moment ago held nothing
/// standing on the floor then, so what stands there now arrived (the "ever-free" idea of
/// occupancy-based dynamic-object detection, kept in 2-D and for a few seconds).
///
/// Guards, so that structure does not pass for motion:
///  - a ray marks no cell within `margin` before its return, and no cell that held a return
///    within the horizon (a ray grazing a pillar crosses the pillar's cell beside it, and a
///    sparse scan does not sample every surface cell in every frame);
///  - a point counts as arrived only when its cell and the eight around it were all crossed
///    (the inside of a box, a wall or a pillar thicker than a cell is never seen through);
///  - heights: an obstacle lower than the band's top may be passed over; an overhang (a table
///    top) above the band is not seen by it, so only points the reference could not judge are
///    asked (MotionTest).
/// Time comes from frame stamps only; an earlier stamp resets the memory.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace ucon {
namespace perception {

struct Frame;

class FreeSpaceMemory {
 public:
  struct Params {
    double horizon = 3.0;     ///< a cell crossed this long ago still counts [s]; 0 = off
    double cell = 0.2;        ///< x-y cell edge [m], > 0
    double min_height = 0.2;  ///< the band a ray must cross a cell in, above the floor [m]
    double max_height = 0.6;  ///< [m], > min_height
    double range = 8.0;       ///< rays are followed this far from the sensor (x-y) [m]
    double margin = 0.3;      ///< no cell within this of a ray's return is marked [m]
    double period = 0.1;      ///< frames are recorded at most this often [s]
  };
  /// A rolling grid sized by sideFor(params).
  /// @throws std::invalid_argument on bad parameters (a programming error: the config reader
  ///         checks the ranges)
  explicit FreeSpaceMemory(const Params& params);
  /// @param cells_per_side the rolling grid's side, a power of two >= 2 (two cells that many
  ///        apart share a slot; the older one is forgotten)
  FreeSpaceMemory(const Params& params, int cells_per_side);
  /// The grid side for `params`: twice the range plus 5 m each way (what the robot drives
  /// within the horizon) in cells, as a power of two, at most 2048 (256 for the shipped values).
  static int sideFor(const Params& params);

  bool enabled() const { return horizon_us_ > 0; }

  /// Records what `frame` saw through, when `period` has passed since the last frame recorded:
  /// frame.returns' rays from frame.sensor_origin, in the band above the floor under the robot
  /// (frame.pose's z), skipping the cells that held one of the recorded frames' points
  /// (frame.points) within the horizon. Call after the frame's points were tested.
  void mark(const Frame& frame);

  /// Whether the cell of `p` and the eight around it were all crossed within `horizon` before
  /// `now` [us], by frames earlier than `now`.
  bool seenFree(const Eigen::Vector3f& p, int64_t now) const;

  void reset();

 private:
  struct Slot {
    int64_t key = INT64_MIN;          ///< packed cell coordinates; INT64_MIN = empty
    int64_t free_utime = INT64_MIN;   ///< last frame that saw through the cell
    int64_t hit_utime = INT64_MIN;    ///< last frame with a return in the cell
  };
  /// Where cell (ix, iy) lives in the rolling grid (shared with the cells side_ apart).
  std::size_t slotIndex(int64_t ix, int64_t iy) const {
    return static_cast<std::size_t>(((iy & mask_) * side_) + (ix & mask_));
  }
  /// The slot of cell (ix, iy), or null when it holds another cell (or none).
  const Slot* find(int64_t ix, int64_t iy) const;
  /// The slot of the cell holding (x, y), emptied first when it held another cell; null for a
  /// non-finite or absurdly far point.
  Slot* claim(float x, float y);
  /// Marks the cells along o + s u, s in [from, to] [m], seen free at `utime`, every half cell.
  void walk(const Eigen::Vector3f& o, const Eigen::Vector2f& u, float from, float to, int64_t utime);

  static constexpr std::size_t kAzimuthBins = 1440;  ///< 0.25 deg: 3.5 cm wide at 8 m

  Params params_;
  int64_t horizon_us_;
  int64_t period_us_;
  float inv_cell_;
  int side_;
  int mask_;
  int64_t last_utime_ = INT64_MIN;
  std::vector<Slot> slots_;
  std::vector<float> extent_;  ///< scratch: per azimuth bin, how far its rays were free [m]
};

}  // namespace perception
}  // namespace ucon
