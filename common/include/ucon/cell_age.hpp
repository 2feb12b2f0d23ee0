#pragma once
/// @file cell_age.hpp
/// Since when each x-y cell has been hit without a long gap, on a rolling grid.
///
/// Two users: perception publishes a point as static structure only once its cell has been
/// occupied for a while (a mover never holds a cell that long), and the planner clears the
/// map under a tracked mover only where the occupancy is young (a ghost the mover left a
/// moment ago, not structure it walks past). Time comes from message stamps only.

#include <cstdint>
#include <vector>

namespace ucon {

class CellAge {
 public:
  static constexpr int64_t kNever = INT64_MIN;  ///< "no current run of hits"

  /// @param cell x-y cell edge [m], > 0
  /// @param max_gap a cell not hit for longer than this starts a new run [s], > 0
  /// @param cells_per_side the rolling grid's side (a power of two >= 2); two cells that many
  ///        cells apart share a slot and overwrite each other, so it must span the area of
  ///        interest twice over (256 cells of 0.2 m: +-25 m)
  /// @throws std::invalid_argument on bad arguments (a programming error, not bad data)
  CellAge(double cell, double max_gap, int cells_per_side);

  /// Records a hit at `utime` [us] of the cell holding (x, y) [m]. Returns the cell's slot,
  /// or -1 for a non-finite or absurdly far point (nothing recorded).
  int hit(int64_t utime, double x, double y);
  /// Packed key of the cell a slot returned by hit() holds now (hold() needs it).
  int64_t slotKey(int slot) const { return slots_[static_cast<std::size_t>(slot)].key; }
  /// Time of the last hit (or hold) of a slot returned by hit() [us].
  int64_t slotLast(int slot) const { return slots_[static_cast<std::size_t>(slot)].last_utime; }
  /// Whether a slot returned by hit() still holds the cell `key` with a run going on at `now`
  /// [us] (last hit or hold at most max_gap before).
  bool running(int slot, int64_t key, int64_t now) const;
  /// Carries the current run of a slot on to `utime` [us] without a hit: the cell was hidden
  /// behind something nearer, which is no evidence that it emptied. Returns false and changes
  /// nothing when the slot holds another cell than `key` now or its run has already ended
  /// (last hit more than max_gap before `utime`).
  bool hold(int slot, int64_t key, int64_t utime);
  /// Start of the current run of hits of a slot returned by hit() [us].
  int64_t slotSince(int slot) const { return slots_[static_cast<std::size_t>(slot)].first_utime; }
  /// Start of the current run of hits of the cell holding (x, y) [us], or kNever when the
  /// cell has none at `now` [us]: never hit, overwritten by another cell, or last hit more
  /// than max_gap before `now`.
  int64_t occupiedSince(double x, double y, int64_t now) const;
  /// Forgets every cell.
  void reset();

 private:
  struct Slot {
    int64_t key = INT64_MIN;  ///< packed cell coordinates; INT64_MIN = empty
    int64_t first_utime = kNever;
    int64_t last_utime = 0;
  };
  /// Packed key and slot of the cell holding (x, y); false for non-finite or far points.
  bool locate(double x, double y, int64_t* key, int* slot) const;
  double inv_cell_;
  int64_t max_gap_us_;
  int side_;
  int mask_;
  std::vector<Slot> slots_;
};

}  // namespace ucon
