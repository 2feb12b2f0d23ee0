#include "leaf_cache.hpp"

#include <algorithm>
#include <cstring>

namespace ucon::planner {

namespace {

uint64_t valueBits(float v) {
  uint32_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

float bitsValue(uint64_t word) {
  const uint32_t b = uint32_t(word);
  float v = 0.0f;
  std::memcpy(&v, &b, sizeof v);
  return v;
}

}  // namespace

LeafCache::LeafCache(const MapParams& p) : tree_(p.resolution) {
  tree_.setProbHit(p.prob_hit);
  tree_.setProbMiss(p.prob_miss);
  // Band-only maps write every leaf through writeLeaf, which records the changed columns
  // itself; OctoMap's change detection is needed for its own full insertion only.
  tree_.enableChangeDetection(!p.band_only);
  band_key_min_ = tree_.coordToKey(p.band_z_min);
  band_key_max_ = tree_.coordToKey(p.band_z_max);
}

void LeafCache::forget() {
  std::fill(cache_.begin(), cache_.end(), 0);
  forgetLeafAddresses();
}

void LeafCache::forgetLeafAddresses() { std::fill(cache_leaf_.begin(), cache_leaf_.end(), nullptr); }

octomap::OcTreeNode* LeafCache::findNode(const octomap::OcTreeKey& k, bool* own) const {
  *own = false;
  octomap::OcTreeNode* node = tree_.getRoot();
  if (node == nullptr) return nullptr;
  for (int depth = int(tree_.getTreeDepth()) - 1; depth >= 0; --depth) {
    const unsigned pos = octomap::computeChildIdx(k, depth);
    if (tree_.nodeChildExists(node, pos)) {
      node = const_cast<octomap::OcTree&>(tree_).getNodeChild(node, pos);
    } else {
      return tree_.nodeHasChildren(node) ? nullptr : node;
    }
  }
  *own = true;
  return node;
}

bool LeafCache::leafValue(const octomap::OcTreeKey& k, float* log_odds) {
  const std::size_t s = cacheSlot(k);
  uint64_t& word = cache_[s];
  const uint64_t tag = cacheTag(k);
  if ((word & kTagMask) != tag) {
    bool own = false;
    octomap::OcTreeNode* n = findNode(k, &own);
    word = n ? (tag | valueBits(n->getLogOdds())) : (tag | kAbsent);
    cache_leaf_[s] = own ? n : nullptr;  // a pruned node covering k is not k's own leaf
  }
  *log_odds = bitsValue(word);
  return (word & kAbsent) == 0;
}

void LeafCache::writeLeaf(const octomap::OcTreeKey& k, bool known, float before, float log_odds) {
  const std::size_t s = cacheSlot(k);
  octomap::OcTreeNode* leaf = cache_leaf_[s];
  if (!leaf && known) {  // its address was forgotten (pruning): find the leaf if it is k's own
    bool own = false;
    octomap::OcTreeNode* n = findNode(k, &own);
    if (own) leaf = n;
  }
  const float thres = tree_.getOccupancyThresLog();
  const bool flipped = (before >= thres) != (log_odds >= thres);
  if (leaf && known) {
    leaf->setLogOdds(log_odds);
    if (flipped) flipped_columns_.emplace_back(k[0], k[1]);
  } else {
    // Lazy: the inner nodes above the leaf are neither re-derived nor pruned. Every reader
    // works on leaves (a search by key descends to the leaf, or to a pruned node whose value
    // its children all had), so the map answers the same; the tree just stays unpruned.
    leaf = tree_.setNodeValue(k, log_odds, /*lazy_eval=*/true);
    // Without OctoMap's change detection (band-only maps: every write comes through here),
    // the change it would record: a leaf created, or one whose occupancy flipped. Its hash
    // map allocated a node per new leaf.
    if (!tree_.isChangeDetectionEnabled() && (!known || flipped) && k[2] >= band_key_min_ && k[2] <= band_key_max_)
      flipped_columns_.emplace_back(k[0], k[1]);
  }
  cache_[s] = cacheTag(k) | valueBits(log_odds);
  cache_leaf_[s] = leaf;
}

void LeafCache::updateLeaf(const octomap::OcTreeKey& k, bool hit) {
  float v = 0.0f;
  const bool exists = leafValue(k, &v);
  const float lo = tree_.getClampingThresMinLog(), hi = tree_.getClampingThresMaxLog();
  const float u = hit ? tree_.getProbHitLog() : tree_.getProbMissLog();
  if (exists && ((u >= 0.0f && v >= hi) || (u <= 0.0f && v <= lo))) return;
  float next = v;  // OcTreeNode::addValue, then OctoMap's clamping
  next += u;
  next = std::min(std::max(next, lo), hi);
  writeLeaf(k, exists, v, next);
}

void LeafCache::pruneIfGrown() {
  if (tree_.size() <= kPruneMinNodes || tree_.size() <= pruned_size_ + pruned_size_ / 2) return;
  prune();
}

void LeafCache::prune() {
  tree_.prune();
  pruned_size_ = tree_.size();
  forgetLeafAddresses();
}

}  // namespace ucon::planner
