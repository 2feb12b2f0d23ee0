#pragma once
/// @file leaf_cache.hpp
/// The planner map's 3-D occupancy tree (OctoMap) and a rolling cache of its leaves, through
/// which every band-only write goes. Private to ucon_planner_map: OctoMap stays out of the
/// public headers.

#include <octomap/OcTree.h>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "ucon/planner/esdf_map.hpp"

namespace ucon::planner {

/// An (x, y) key pair: one column of the tree.
using ColumnKey = std::pair<octomap::key_type, octomap::key_type>;

/// The 3-D map (ray insertion, all heights) with the log-odds of its leaves cached on a
/// rolling grid (slot -> tagged key; 0 = nothing known), so that the insertion and the
/// projection rarely search the tree. A tag with kAbsent set records that no leaf (and no
/// pruned node) covers the key. Exact: every write to the tree goes through writeLeaf or the
/// all-heights insertion (which calls forget()); pruning keeps every leaf's value (a pruned
/// node holds the value its children all had). Most rays of every scan cross leaves at a
/// clamping bound, where a hit or miss changes nothing and is skipped as OctoMap's updateNode
/// would.
///
/// A slot also keeps the address of its leaf once a write has reached it: the next write sets
/// the value in place instead of descending the tree's 16 levels again (one cache miss instead
/// of sixteen). Leaves are deleted only by pruning, which forgets every address. Writes in
/// place bypass OctoMap's change detection; the columns whose occupancy they flip are
/// collected in flippedColumns() for the projection.
class LeafCache {
 public:
  explicit LeafCache(const MapParams& params);
  LeafCache(const LeafCache&) = delete;
  LeafCache& operator=(const LeafCache&) = delete;

  octomap::OcTree& tree() { return tree_; }
  const octomap::OcTree& tree() const { return tree_; }
  /// Keys of the lowest and highest leaf layer of the robot's height band.
  octomap::key_type bandKeyMin() const { return band_key_min_; }
  octomap::key_type bandKeyMax() const { return band_key_max_; }

  /// The log-odds of leaf k (false when no node covers it), from the cache or a tree search.
  bool leafValue(const octomap::OcTreeKey& k, float* log_odds);
  /// Sets leaf k to `log_odds` (within the clamping bounds), as OctoMap's lazy setNodeValue
  /// would. `known` / `before`: what leafValue said about it.
  void writeLeaf(const octomap::OcTreeKey& k, bool known, float before, float log_odds);
  /// A hit or miss on leaf k: the same leaf value as OctoMap's updateNode (a new leaf starts
  /// at 0, the update is added and clamped). Skipped when the leaf already sits at the bound
  /// the update pushes it to.
  void updateLeaf(const octomap::OcTreeKey& k, bool hit);

  /// Forgets every cached value and leaf address (after a write that bypassed the cache).
  void forget();
  /// The lazy updates leave subtrees whose leaves all agree unpruned: the tree is pruned
  /// whenever it has grown by half since the last pruning (amortised O(1) per node; the tree
  /// stays within half again the size it had after the last pruning).
  void pruneIfGrown();
  void prune();

  /// Columns of the band whose occupancy writeLeaf changed without OctoMap's change detection
  /// seeing it (the projection takes and clears them).
  std::vector<ColumnKey>& flippedColumns() { return flipped_columns_; }

 private:
  static constexpr std::size_t kCacheSlots = std::size_t(1) << 20;
  static constexpr uint64_t kKnown = uint64_t(1) << 63, kAbsent = uint64_t(1) << 62;
  static constexpr uint64_t kTagMask = ~uint64_t(0xffffffffu) & ~kAbsent;
  static constexpr std::size_t kPruneMinNodes = 4096;

  static std::size_t cacheSlot(const octomap::OcTreeKey& k) {
    // x fastest: a ray's neighbouring cells along x share a cache line.
    return (std::size_t(k[2] & 15) << 16) | (std::size_t(k[1] & 255) << 8) | std::size_t(k[0] & 255);
  }
  static uint64_t cacheTag(const octomap::OcTreeKey& k) {  // the bits cacheSlot drops
    return kKnown | (uint64_t(k[0] >> 8) << 32) | (uint64_t(k[1] >> 8) << 40) | (uint64_t(k[2] >> 4) << 48);
  }
  void forgetLeafAddresses();
  /// The node OcTree::search(k) returns (the leaf of k, or a pruned node covering it; null
  /// when none covers it), by the same descent; `own` says whether it is k's own leaf at full
  /// depth, which a write may then set in place.
  octomap::OcTreeNode* findNode(const octomap::OcTreeKey& k, bool* own) const;

  octomap::OcTree tree_;
  octomap::key_type band_key_min_ = 0, band_key_max_ = 0;
  /// A slot's word: kKnown | kAbsent? | the key's bits its index does not hold << 32 | the
  /// value's bits. The leaf addresses sit apart (read only to write a leaf): lookups, most of
  /// them misses on leaves at a bound, touch 8 bytes per slot.
  std::vector<uint64_t> cache_ = std::vector<uint64_t>(kCacheSlots, 0);
  std::vector<octomap::OcTreeNode*> cache_leaf_ = std::vector<octomap::OcTreeNode*>(kCacheSlots, nullptr);
  std::vector<ColumnKey> flipped_columns_;
  std::size_t pruned_size_ = 0;
};

}  // namespace ucon::planner
