#include "ucon/cell_age.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ucon {

CellAge::CellAge(double cell, double max_gap, int cells_per_side)
    : inv_cell_(1.0 / cell),
      max_gap_us_(static_cast<int64_t>(std::llround(max_gap * 1e6))),
      side_(cells_per_side),
      mask_(cells_per_side - 1) {
  if (!(cell > 0.0) || !(max_gap > 0.0)) throw std::invalid_argument("CellAge: cell and max_gap must be > 0");
  if (cells_per_side < 2 || (cells_per_side & (cells_per_side - 1)) != 0)
    throw std::invalid_argument("CellAge: cells_per_side must be a power of two >= 2");
  reset();
}

void CellAge::reset() { slots_.assign(static_cast<std::size_t>(side_) * static_cast<std::size_t>(side_), Slot{}); }

bool CellAge::locate(double x, double y, int64_t* key, int* slot) const {
  const double fx = std::floor(x * inv_cell_);
  const double fy = std::floor(y * inv_cell_);
  if (!std::isfinite(fx) || !std::isfinite(fy) || std::abs(fx) > 1e9 || std::abs(fy) > 1e9) return false;
  const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  // Shifted as unsigned: left-shifting a negative signed value is undefined in C++17.
  *key = static_cast<int64_t>((static_cast<uint64_t>(ix) << 32) ^ (static_cast<uint64_t>(iy) & 0xffffffffULL));
  *slot = static_cast<int>(((iy & mask_) * side_) + (ix & mask_));
  return true;
}

int CellAge::hit(int64_t utime, double x, double y) {
  int64_t key = 0;
  int s = -1;
  if (!locate(x, y, &key, &s)) return -1;
  Slot& slot = slots_[static_cast<std::size_t>(s)];
  if (slot.key != key || utime - slot.last_utime > max_gap_us_) {
    slot.key = key;
    slot.first_utime = utime;
  }
  slot.last_utime = utime;
  return s;
}

bool CellAge::running(int slot, int64_t key, int64_t now) const {
  if (slot < 0 || static_cast<std::size_t>(slot) >= slots_.size()) return false;
  const Slot& s = slots_[static_cast<std::size_t>(slot)];
  return s.key == key && s.first_utime != kNever && now - s.last_utime <= max_gap_us_;
}

bool CellAge::hold(int slot, int64_t key, int64_t utime) {
  if (!running(slot, key, utime)) return false;
  Slot& s = slots_[static_cast<std::size_t>(slot)];
  s.last_utime = std::max(s.last_utime, utime);
  return true;
}

int64_t CellAge::occupiedSince(double x, double y, int64_t now) const {
  int64_t key = 0;
  int s = -1;
  if (!locate(x, y, &key, &s)) return kNever;
  const Slot& slot = slots_[static_cast<std::size_t>(s)];
  if (slot.key != key || now - slot.last_utime > max_gap_us_) return kNever;
  return slot.first_utime;
}

}  // namespace ucon
