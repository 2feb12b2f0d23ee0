#include "ucon/planner/esdf_map.hpp"

#include <dynamicEDT3D/dynamicEDTOctomap.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <exception>
#include <iterator>
#include <limits>
#include <mutex>
#include <thread>
#include <utility>

#include "ucon/config.hpp"
#include "ucon/cpu_time.hpp"
#include "ucon/static_points_t.hpp"

namespace ucon::planner {

void MapParams::read(ConfigReader& r) {
  r.read("resolution", resolution, 0.02, 1.0);
  r.read("max_range", max_range, 0.5, 100.0);
  r.read("band_z_min", band_z_min, -10.0, 10.0);
  r.read("band_z_max", band_z_max, -10.0, 10.0);
  r.read("box_half_size", box_half_size, 1.0, 50.0);
  r.read("recenter_distance", recenter_distance, 0.0, 50.0);
  r.read("max_distance", max_distance, 0.05, 20.0);
  r.read("prob_hit", prob_hit, 0.5, 1.0);
  r.read("prob_miss", prob_miss, 0.0, 0.5);
  r.read("band_only", band_only);
  r.read("insert_threads", insert_threads, 1, 2);
  const std::string why = validate();
  if (!why.empty()) r.fail(why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
}

std::string MapParams::validate() const {
  if (!(resolution > 0.0)) return "resolution: must be > 0";
  if (!(band_z_max > band_z_min)) return "band_z_max: must be greater than band_z_min";
  if (!(max_distance > resolution)) return "max_distance: must exceed resolution";
  if (!(recenter_distance < box_half_size)) return "recenter_distance: must be below box_half_size";
  if (!(max_range > 0.0)) return "max_range: must be > 0";
  if (insert_threads < 1 || insert_threads > 2) return "insert_threads: must be 1 or 2";
  return {};
}

const char* toString(InsertStatus s) {
  switch (s) {
    case InsertStatus::kOk: return "ok";
    case InsertStatus::kInvalidMessage: return "invalid message (valid=false, utime<=0 or bad sizes)";
    case InsertStatus::kBadOrigin: return "sensor origin not finite";
    case InsertStatus::kEmpty: return "no finite points";
  }
  return "unknown";
}

namespace {

/// 1-D squared distance transform (Felzenszwalb & Huttenlocher 2012) of f over n samples,
/// unit spacing, into d. v, z are scratch of size n and n+1.
void distanceTransform1d(const float* f, int n, float* d, int* v, float* z) {
  const float inf = std::numeric_limits<float>::infinity();
  int k = 0;
  int first = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] < inf) {
      first = q;
      break;
    }
  }
  if (first < 0) {
    for (int q = 0; q < n; ++q) d[q] = inf;
    return;
  }
  v[0] = first;
  z[0] = -inf;
  z[1] = inf;
  for (int q = first + 1; q < n; ++q) {
    if (!(f[q] < inf)) continue;
    float s;
    while (true) {
      const int p = v[k];
      s = ((f[q] + float(q) * q) - (f[p] + float(p) * p)) / (2.0f * (q - p));
      if (s <= z[k] && k > 0) {
        --k;
        continue;
      }
      break;
    }
    if (s <= z[k]) {  // k == 0 and the new parabola dominates everywhere
      v[0] = q;
      z[0] = -inf;
      z[1] = inf;
      continue;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = inf;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const float dq = float(q - v[k]);
    d[q] = dq * dq + f[v[k]];
  }
}

/// The keys OctoMap's OcTree::computeRayKeys(origin, end, ray) would put into `ray`, in the
/// same order, handed to `visit(key)` one by one instead of being stored: the same 3-D DDA
/// (Amanatides & Woo) with the same arithmetic, so the same cells (tested against
/// computeRayKeys on random rays). False, visiting nothing, when an end lies outside the tree.
template <class Visit>
bool traceRayKeys(const octomap::OcTree& t, const octomap::point3d& origin, const octomap::point3d& end,
                  Visit&& visit) {
  octomap::OcTreeKey key_origin, key_end;
  if (!t.coordToKeyChecked(origin, key_origin) || !t.coordToKeyChecked(end, key_end)) return false;
  if (key_origin == key_end) return true;
  visit(key_origin);
  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;
  const double resolution = t.getResolution();
  int step[3];
  double t_max[3], t_delta[3];
  octomap::OcTreeKey current = key_origin;
  for (unsigned i = 0; i < 3; ++i) {
    step[i] = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    if (step[i] != 0) {
      double border = t.keyToCoord(current[i]);
      border += float(step[i] * resolution * 0.5);
      t_max[i] = (border - origin(i)) / direction(i);
      t_delta[i] = resolution / std::fabs(direction(i));
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  while (true) {
    unsigned dim;
    if (t_max[0] < t_max[1]) {
      dim = t_max[0] < t_max[2] ? 0 : 2;
    } else {
      dim = t_max[1] < t_max[2] ? 1 : 2;
    }
    current[dim] = octomap::key_type(current[dim] + step[dim]);
    t_max[dim] += t_delta[dim];
    if (current == key_end) return true;
    if (std::min(std::min(t_max[0], t_max[1]), t_max[2]) > length) return true;
    visit(current);
  }
}

/// A thread that runs one job at a time for the insertion: start() hands it a job, wait()
/// returns once it is done (rethrowing what it threw).
class InsertHelper {
 public:
  InsertHelper() : thread_([this] { run(); }) {}
  ~InsertHelper() {
    {
      std::lock_guard<std::mutex> lk(m_);
      quit_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  InsertHelper(const InsertHelper&) = delete;
  InsertHelper& operator=(const InsertHelper&) = delete;

  void start(std::function<void()> job) {
    {
      std::lock_guard<std::mutex> lk(m_);
      job_ = std::move(job);
      busy_ = true;
    }
    cv_.notify_all();
  }
  void wait() {
    std::unique_lock<std::mutex> lk(m_);
    cv_.wait(lk, [&] { return !busy_; });
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }
  double cpuSeconds() const {
    std::lock_guard<std::mutex> lk(m_);
    return cpu_s_;
  }

 private:
  void run() {
    std::unique_lock<std::mutex> lk(m_);
    for (;;) {
      cv_.wait(lk, [&] { return quit_ || busy_; });
      if (!busy_) return;  // quit with no job pending
      std::function<void()> job = std::move(job_);
      lk.unlock();
      const double cpu0 = threadCpuSeconds();
      std::exception_ptr error;
      try {
        job();
      } catch (...) {
        error = std::current_exception();
      }
      const double cpu = threadCpuSeconds() - cpu0;
      lk.lock();
      cpu_s_ += cpu;
      error_ = error;
      busy_ = false;
      cv_.notify_all();
    }
  }

  mutable std::mutex m_;
  std::condition_variable cv_;
  std::function<void()> job_;
  bool busy_ = false, quit_ = false;
  std::exception_ptr error_;
  double cpu_s_ = 0.0;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace

struct EsdfMap::Impl {
  MapParams params;
  /// The 3-D map: ray insertion, all heights.
  octomap::OcTree tree;
  /// Its projection onto one layer: a leaf is occupied when any leaf of the height band above
  /// it is. The distance transform runs on this single layer, so its cost does not grow with
  /// the band's height and a 2-D query is one lookup.
  octomap::OcTree flat;
  octomap::key_type band_key_min = 0, band_key_max = 0;
  std::unique_ptr<DynamicEDTOctomap> edt;
  octomap::OcTreeKey key_min, key_max;
  Eigen::Vector2d box_center = Eigen::Vector2d::Zero();
  SliceGeometry slice;
  std::vector<float> values;  // signed distance per slice cell, row-major (iy * nx + ix)
  std::vector<uint8_t> occupied;
  std::vector<float> scratch_f, scratch_d, scratch_z, scratch_col;
  std::vector<int> scratch_v;
  std::vector<uint64_t> scratch_endpoints, scratch_free_outside, scratch_occupied;  // band-only insertion
  std::vector<uint64_t> scratch_endpoints_outside;  // ... its endpoint leaves outside its grid
  std::vector<octomap::point3d> scratch_ray_ends;   // ... where each endpoint's ray is traced to
  std::vector<uint64_t> seen;  // ... its per-cell dedup bits (endpoints; then cells updated, or occupied: to be)
  // The helper's share of a two-thread insertion: its own dedup bits, the cells new to its
  // rays in order, and its cells outside the grid.
  std::unique_ptr<InsertHelper> helper;
  std::vector<uint64_t> helper_seen;
  std::vector<octomap::OcTreeKey> helper_fresh;
  std::vector<uint64_t> helper_free_outside;
  /// Log-odds of leaves on a rolling grid (slot -> tagged key; 0 = nothing known), so that the
  /// insertion and the projection rarely search the tree. A tag with kAbsent set records that
  /// no leaf (and no pruned node) covers the key. Exact: every write to the tree goes through
  /// writeLeaf or the all-heights insertion (which forgets the cache); pruning keeps every
  /// leaf's value (a pruned node holds the value its children all had). Most rays of every
  /// scan cross leaves at a clamping bound, where a hit or miss changes nothing and is skipped
  /// as OctoMap's updateNode would.
  ///
  /// A slot also keeps the address of its leaf once a write has reached it: the next write
  /// sets the value in place instead of descending the tree's 16 levels again (one cache miss
  /// instead of sixteen). Leaves are deleted only by pruning, which forgets every address.
  /// Writes in place bypass OctoMap's change detection; the columns whose occupancy they
  /// flip are collected in `flipped_columns` for syncProjection.
  static constexpr std::size_t kCacheSlots = std::size_t(1) << 20;
  static constexpr uint64_t kKnown = uint64_t(1) << 63, kAbsent = uint64_t(1) << 62;
  static constexpr uint64_t kTagMask = ~uint64_t(0xffffffffu) & ~kAbsent;
  /// A slot's word: kKnown | kAbsent? | the key's bits its index does not hold << 32 | the
  /// value's bits. The leaf addresses sit apart (read only to write a leaf): lookups, most of
  /// them misses on leaves at a bound, touch 8 bytes per slot.
  std::vector<uint64_t> cache = std::vector<uint64_t>(kCacheSlots, 0);
  std::vector<octomap::OcTreeNode*> cache_leaf = std::vector<octomap::OcTreeNode*>(kCacheSlots, nullptr);
  std::vector<std::pair<octomap::key_type, octomap::key_type>> flipped_columns;
  static std::size_t cacheSlot(const octomap::OcTreeKey& k) {
    // x fastest: a ray's neighbouring cells along x share a cache line.
    return (std::size_t(k[2] & 15) << 16) | (std::size_t(k[1] & 255) << 8) | std::size_t(k[0] & 255);
  }
  static uint64_t cacheTag(const octomap::OcTreeKey& k) {  // the bits cacheSlot drops
    return kKnown | (uint64_t(k[0] >> 8) << 32) | (uint64_t(k[1] >> 8) << 40) | (uint64_t(k[2] >> 4) << 48);
  }
  static uint64_t valueBits(float v) {
    uint32_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
  }
  static float bitsValue(uint64_t word) {
    const uint32_t b = uint32_t(word);
    float v = 0.0f;
    std::memcpy(&v, &b, sizeof v);
    return v;
  }
  void forgetCache() { std::fill(cache.begin(), cache.end(), 0); }
  void forgetLeafAddresses() { std::fill(cache_leaf.begin(), cache_leaf.end(), nullptr); }
  /// The node OcTree::search(k) returns (the leaf of k, or a pruned node covering it; null
  /// when none covers it), by the same descent; `own` says whether it is k's own leaf at full
  /// depth, which a write may then set in place.
  octomap::OcTreeNode* findNode(const octomap::OcTreeKey& k, bool* own) const {
    *own = false;
    octomap::OcTreeNode* node = tree.getRoot();
    if (node == nullptr) return nullptr;
    for (int depth = int(tree.getTreeDepth()) - 1; depth >= 0; --depth) {
      const unsigned pos = octomap::computeChildIdx(k, depth);
      if (tree.nodeChildExists(node, pos)) {
        node = const_cast<octomap::OcTree&>(tree).getNodeChild(node, pos);
      } else {
        return tree.nodeHasChildren(node) ? nullptr : node;
      }
    }
    *own = true;
    return node;
  }
  /// The log-odds of leaf k (false when no node covers it), from the cache or a tree search.
  bool leafValue(const octomap::OcTreeKey& k, float* log_odds) {
    const std::size_t s = cacheSlot(k);
    uint64_t& word = cache[s];
    const uint64_t tag = cacheTag(k);
    if ((word & kTagMask) != tag) {
      bool own = false;
      octomap::OcTreeNode* n = findNode(k, &own);
      word = n ? (tag | valueBits(n->getLogOdds())) : (tag | kAbsent);
      cache_leaf[s] = own ? n : nullptr;  // a pruned node covering k is not k's own leaf
    }
    *log_odds = bitsValue(word);
    return (word & kAbsent) == 0;
  }
  /// Sets leaf k to `log_odds` (within the clamping bounds), as OctoMap's lazy setNodeValue
  /// would. `known` / `before`: what leafValue said about it.
  void writeLeaf(const octomap::OcTreeKey& k, bool known, float before, float log_odds) {
    const std::size_t s = cacheSlot(k);
    octomap::OcTreeNode* leaf = cache_leaf[s];
    if (!leaf && known) {  // its address was forgotten (pruning): find the leaf if it is k's own
      bool own = false;
      octomap::OcTreeNode* n = findNode(k, &own);
      if (own) leaf = n;
    }
    const float thres = tree.getOccupancyThresLog();
    const bool flipped = (before >= thres) != (log_odds >= thres);
    if (leaf && known) {
      leaf->setLogOdds(log_odds);
      if (flipped) flipped_columns.emplace_back(k[0], k[1]);
    } else {
      // Lazy: the inner nodes above the leaf are neither re-derived nor pruned. Every reader
      // works on leaves (a search by key descends to the leaf, or to a pruned node whose value
      // its children all had), so the map answers the same; the tree just stays unpruned.
      leaf = tree.setNodeValue(k, log_odds, /*lazy_eval=*/true);
      // Without OctoMap's change detection (band-only maps: every write comes through here),
      // the change it would record: a leaf created, or one whose occupancy flipped. Its hash
      // map allocated a node per new leaf.
      if (!tree.isChangeDetectionEnabled() && (!known || flipped) && k[2] >= band_key_min && k[2] <= band_key_max)
        flipped_columns.emplace_back(k[0], k[1]);
    }
    cache[s] = cacheTag(k) | valueBits(log_odds);
    cache_leaf[s] = leaf;
  }
  /// A hit or miss on leaf k: the same leaf value as OctoMap's updateNode (a new leaf starts
  /// at 0, the update is added and clamped). Skipped when the leaf already sits at the bound
  /// the update pushes it to.
  void updateLeaf(const octomap::OcTreeKey& k, bool hit) {
    float v = 0.0f;
    const bool exists = leafValue(k, &v);
    const float lo = tree.getClampingThresMinLog(), hi = tree.getClampingThresMaxLog();
    const float u = hit ? tree.getProbHitLog() : tree.getProbMissLog();
    if (exists && ((u >= 0.0f && v >= hi) || (u <= 0.0f && v <= lo))) return;
    float next = v;  // OcTreeNode::addValue, then OctoMap's clamping
    next += u;
    next = std::min(std::max(next, lo), hi);
    writeLeaf(k, exists, v, next);
  }
  /// The lazy updates leave subtrees whose leaves all agree unpruned: the tree is pruned
  /// whenever it has grown by half since the last pruning (amortised O(1) per node; the tree
  /// stays within half again the size it had after the last pruning).
  std::size_t pruned_size = 0;
  void pruneIfGrown() {
    if (tree.size() <= kPruneMinNodes || tree.size() <= pruned_size + pruned_size / 2) return;
    prune();
  }
  void prune() {
    tree.prune();
    pruned_size = tree.size();
    forgetLeafAddresses();
  }
  static constexpr std::size_t kPruneMinNodes = 4096;
  std::vector<std::pair<octomap::key_type, octomap::key_type>> dirty_columns;
  int64_t incremental = 0;
  int64_t rebuilds = 0;

  explicit Impl(const MapParams& p) : params(p), tree(p.resolution), flat(p.resolution) {
    tree.setProbHit(p.prob_hit);
    tree.setProbMiss(p.prob_miss);
    // Band-only maps write every leaf through writeLeaf, which records the changed columns
    // itself; OctoMap's change detection is needed for its own full insertion only.
    tree.enableChangeDetection(!p.band_only);
    flat.enableChangeDetection(true);
    band_key_min = tree.coordToKey(p.band_z_min);
    band_key_max = tree.coordToKey(p.band_z_max);
  }

  /// Brings the projection up to date with the 3-D cells changed since the last call.
  void syncProjection() {
    dirty_columns.clear();
    for (auto it = tree.changedKeysBegin(), end = tree.changedKeysEnd(); it != end; ++it) {
      const octomap::OcTreeKey& k = it->first;
      if (k[2] < band_key_min || k[2] > band_key_max) continue;
      dirty_columns.emplace_back(k[0], k[1]);
    }
    tree.resetChangeDetection();
    dirty_columns.insert(dirty_columns.end(), flipped_columns.begin(), flipped_columns.end());
    flipped_columns.clear();
    std::sort(dirty_columns.begin(), dirty_columns.end());
    dirty_columns.erase(std::unique(dirty_columns.begin(), dirty_columns.end()), dirty_columns.end());
    for (const auto& [kx, ky] : dirty_columns) {
      bool occ = false;
      for (octomap::key_type kz = band_key_min; kz <= band_key_max && !occ; ++kz) {
        float v = 0.0f;
        occ = leafValue(octomap::OcTreeKey(kx, ky, kz), &v) && v >= tree.getOccupancyThresLog();
      }
      const octomap::OcTreeKey fk(kx, ky, band_key_min);
      const auto* existing = flat.search(fk);
      if (existing ? flat.isNodeOccupied(existing) == occ : !occ) continue;  // unchanged (unknown = free)
      flat.setNodeValue(fk, occ ? flat.getClampingThresMaxLog() : flat.getClampingThresMinLog());
      flat_changed.emplace_back(kx, ky);
    }
  }
  /// Projection cells whose occupancy changed since the slice was last computed.
  std::vector<std::pair<octomap::key_type, octomap::key_type>> flat_changed;
  std::vector<uint8_t> dirty;  // per slice cell: to be recomputed (incremental computeSlice)

  void rebuild(const Eigen::Vector2d& c) {
    const double h = params.box_half_size;
    const float z = float(tree.keyToCoord(band_key_min));
    const octomap::point3d lo(float(c.x() - h), float(c.y() - h), z);
    const octomap::point3d hi(float(c.x() + h), float(c.y() + h), z);
    edt.reset();  // free the old grid before allocating the new one
    edt = std::make_unique<DynamicEDTOctomap>(float(params.max_distance), &flat, lo, hi, false);
    // The constructor read the whole box from the projection: pending changes are in it.
    flat.resetChangeDetection();
    edt->update(true);
    key_min = flat.coordToKey(lo);
    key_max = flat.coordToKey(hi);
    box_center = c;
    ++rebuilds;
  }

  /// The slice's value of cell (ix, iy) from the distance transform (occupied: 0 for now, see
  /// computeInterior).
  void sliceCell(int ix, int iy, float half, float cap) {
    const octomap::OcTreeKey k(key_min[0] + ix, key_min[1] + iy, key_min[2]);
    const float dmin = edt->getDistance_unsafe(k);
    const std::size_t i = std::size_t(iy) * std::size_t(slice.nx) + std::size_t(ix);
    if (dmin <= 0.0f) {
      occupied[i] = 1;
      values[i] = 0.0f;
    } else {
      // Distance from this cell centre to the nearest occupied cell's boundary (approx.).
      occupied[i] = 0;
      values[i] = std::min(cap, dmin - half);
    }
  }

  /// Fills the 2-D slice from the distance transform. `full` after a rebuild; otherwise only
  /// the cells near projection cells that changed since the last call: a change moves the
  /// distance transform only within max_distance of it, and the interior distances only
  /// within max_distance + half a cell, so every other cell keeps its value (same values as
  /// a full pass, tested).
  void computeSlice(bool full) {
    const int nx = key_max[0] - key_min[0] + 1;
    const int ny = key_max[1] - key_min[1] + 1;
    const double res = tree.getResolution();
    const float half = float(0.5 * res);
    const float cap = float(params.max_distance);
    const std::size_t n = std::size_t(nx) * std::size_t(ny);
    if (full || slice.nx != nx || slice.ny != ny || values.size() != n) {
      const octomap::point3d corner = tree.keyToCoord(key_min);
      slice.origin = Eigen::Vector2d(corner.x() - 0.5 * res, corner.y() - 0.5 * res);
      slice.resolution = res;
      slice.nx = nx;
      slice.ny = ny;
      values.assign(n, 0.0f);
      occupied.assign(n, 0);
      for (int iy = 0; iy < ny; ++iy)
        for (int ix = 0; ix < nx; ++ix) sliceCell(ix, iy, half, cap);
      flat_changed.clear();
      computeInterior();
      return;
    }
    if (flat_changed.empty()) return;
    // Cells within r of a change (Chebyshev, in cells) and their bounding box.
    const int r = int(std::ceil((params.max_distance + res) / res)) + 2;
    dirty.assign(n, 0);
    int x0 = nx, y0 = ny, x1 = -1, y1 = -1;
    for (const auto& [kx, ky] : flat_changed) {
      const int cx = int(kx) - int(key_min[0]), cy = int(ky) - int(key_min[1]);
      const int ax = std::max(0, cx - r), bx = std::min(nx - 1, cx + r);
      const int ay = std::max(0, cy - r), by = std::min(ny - 1, cy + r);
      if (ax > bx || ay > by) continue;  // outside the box
      for (int iy = ay; iy <= by; ++iy)
        std::fill(dirty.begin() + std::ptrdiff_t(std::size_t(iy) * nx + ax),
                  dirty.begin() + std::ptrdiff_t(std::size_t(iy) * nx + bx + 1), uint8_t(1));
      x0 = std::min(x0, ax), y0 = std::min(y0, ay), x1 = std::max(x1, bx), y1 = std::max(y1, by);
    }
    flat_changed.clear();
    if (x1 < 0) return;
    for (int iy = y0; iy <= y1; ++iy)
      for (int ix = x0; ix <= x1; ++ix)
        if (dirty[std::size_t(iy) * nx + ix]) sliceCell(ix, iy, half, cap);
    // Interior distances of the dirty cells: the nearest free cell by a search outwards.
    interiorNear(x0, y0, x1, y1);
  }

  /// Offsets (dx, dy) within the interior search radius, by increasing dx^2 + dy^2.
  struct RingOffset {
    int dx, dy, d2;
  };
  std::vector<RingOffset> ring;
  int ring_radius = -1;
  /// The interior distance of every occupied dirty cell in [x0, x1] x [y0, y1]: the same value
  /// computeInterior gives (minus the distance to the nearest free cell of the slice, less half
  /// a cell, capped), found by trying the cells around it nearest first. Obstacles are thin
  /// shells of surface hits, so a free cell is most often a neighbour. A cell with no free cell
  /// within R = (cap + half a cell) / resolution + 1 cells gets -cap, as it does there.
  void interiorNear(int x0, int y0, int x1, int y1) {
    const int nx = slice.nx, ny = slice.ny;
    const float res = float(slice.resolution);
    const float half = 0.5f * res;
    const float cap = float(params.max_distance);
    const int R = int(std::ceil((params.max_distance + 0.5 * slice.resolution) / slice.resolution)) + 1;
    if (R != ring_radius) {
      ring.clear();
      for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx)
          if (dx * dx + dy * dy <= R * R) ring.push_back({dx, dy, dx * dx + dy * dy});
      std::stable_sort(ring.begin(), ring.end(), [](const RingOffset& a, const RingOffset& b) { return a.d2 < b.d2; });
      ring_radius = R;
    }
    for (int iy = y0; iy <= y1; ++iy)
      for (int ix = x0; ix <= x1; ++ix) {
        const std::size_t i = std::size_t(iy) * nx + ix;
        if (!dirty[i] || !occupied[i]) continue;
        float v = -cap;
        for (const RingOffset& o : ring) {
          const int qx = ix + o.dx, qy = iy + o.dy;
          if (qx < 0 || qy < 0 || qx >= nx || qy >= ny || occupied[std::size_t(qy) * nx + qx]) continue;
          v = interiorValue(std::sqrt(float(o.d2)) * res, half, cap);
          break;
        }
        values[i] = v;
      }
  }

  /// The slice recomputed in full from the distance transform, compared value for value with
  /// the incrementally kept one: the number of differing cells.
  std::size_t sliceMismatches() {
    const std::vector<float> kept_values = values;
    const std::vector<uint8_t> kept_occupied = occupied;
    const auto kept_changed = flat_changed;
    computeSlice(true);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < values.size(); ++i)
      bad += (values[i] != kept_values[i] || occupied[i] != kept_occupied[i]) ? 1 : 0;
    values = kept_values;
    occupied = kept_occupied;
    flat_changed = kept_changed;
    return bad;
  }

  /// An occupied cell's value from the distance `din` [m] between its centre and the nearest
  /// free cell's centre (infinite: none): minus that distance less half a cell, capped.
  static float interiorValue(float din, float half, float cap) {
    return std::isfinite(din) ? -std::min(cap, din - half) : -cap;
  }

  /// Inside obstacles, over the whole slice: minus the distance to the nearest free cell (so
  /// the optimiser has a gradient that pushes out of an obstacle instead of a flat zero).
  void computeInterior() {
    const int nx = slice.nx, ny = slice.ny;
    if (nx <= 0 || ny <= 0) return;
    if (std::find(occupied.begin(), occupied.end(), uint8_t(1)) == occupied.end()) return;
    const float half = float(0.5 * slice.resolution);
    const float cap = float(params.max_distance);
    const float inf = std::numeric_limits<float>::infinity();
    const int m = std::max(nx, ny);
    scratch_f.resize(std::size_t(nx) * ny);
    scratch_col.resize(m);
    scratch_d.resize(m);
    scratch_z.resize(m + 1);
    scratch_v.resize(m);
    for (std::size_t i = 0; i < scratch_f.size(); ++i) scratch_f[i] = occupied[i] ? inf : 0.0f;
    // Columns (along y) then rows (along x).
    for (int ix = 0; ix < nx; ++ix) {
      for (int iy = 0; iy < ny; ++iy) scratch_col[iy] = scratch_f[std::size_t(iy) * nx + ix];
      distanceTransform1d(scratch_col.data(), ny, scratch_d.data(), scratch_v.data(), scratch_z.data());
      for (int iy = 0; iy < ny; ++iy) scratch_f[std::size_t(iy) * nx + ix] = scratch_d[iy];
    }
    for (int iy = 0; iy < ny; ++iy) {
      float* row = &scratch_f[std::size_t(iy) * nx];
      distanceTransform1d(row, nx, scratch_d.data(), scratch_v.data(), scratch_z.data());
      for (int ix = 0; ix < nx; ++ix) {
        const std::size_t i = std::size_t(iy) * nx + ix;
        if (occupied[i]) values[i] = interiorValue(std::sqrt(scratch_d[ix]) * float(slice.resolution), half, cap);
      }
    }
  }
};

EsdfMap::EsdfMap(const MapParams& params) : impl_(std::make_unique<Impl>(params)) {}
EsdfMap::~EsdfMap() = default;

InsertStatus EsdfMap::insert(const static_points_t& msg, int64_t* skipped) {
  if (!msg.valid || msg.utime <= 0 || msg.num_points < 0 ||
      msg.x.size() != std::size_t(msg.num_points) || msg.y.size() != std::size_t(msg.num_points) ||
      msg.z.size() != std::size_t(msg.num_points)) {
    return InsertStatus::kInvalidMessage;
  }
  std::vector<Eigen::Vector3f> pts(std::size_t(msg.num_points));
  for (int i = 0; i < msg.num_points; ++i) pts[i] = Eigen::Vector3f(msg.x[i], msg.y[i], msg.z[i]);
  double range = impl_->params.max_range;
  if (std::isfinite(msg.max_range) && msg.max_range > 0.0f) range = std::min(range, double(msg.max_range));
  return insert(Eigen::Vector3d(msg.origin_x, msg.origin_y, msg.origin_z), pts, range, skipped);
}

InsertStatus EsdfMap::insert(const Eigen::Vector3d& origin, const std::vector<Eigen::Vector3f>& points,
                             double max_range, int64_t* skipped) {
  if (!origin.allFinite()) return InsertStatus::kBadOrigin;
  Impl& m = *impl_;
  const double range = (std::isfinite(max_range) && max_range > 0.0) ? max_range : m.params.max_range;
  const octomap::point3d o(float(origin.x()), float(origin.y()), float(origin.z()));
  int64_t bad = 0;
  if (!m.params.band_only) {
    octomap::Pointcloud cloud;
    cloud.reserve(points.size());
    for (const auto& p : points) {
      if (p.allFinite()) {
        cloud.push_back(p.x(), p.y(), p.z());
      } else {
        ++bad;
      }
    }
    if (skipped) *skipped += bad;
    if (cloud.size() == 0) return InsertStatus::kEmpty;
    m.tree.insertPointCloud(cloud, o, range, /*lazy_eval=*/false, /*discretize=*/true);
    m.forgetCache();  // unknown which leaves changed; insertPointCloud prunes
    m.forgetLeafAddresses();
    return InsertStatus::kOk;
  }
  // The same update as OctoMap's discretised insertPointCloud, restricted to the height band:
  // each ray is traced only until it leaves the band's slab (one leaf of margin), because the
  // cells beyond cannot change the band. The band's cells get exactly the updates of a full
  // insertion (a clipped ray visits a prefix of the full ray's cells), at a fraction of the
  // work: the sensor sits in the band and most returns lie above it.
  octomap::OcTree& t = m.tree;
  const double res = t.getResolution();
  const double z_lo = t.keyToCoord(m.band_key_min) - 1.5 * res;
  const double z_hi = t.keyToCoord(m.band_key_max) + 1.5 * res;
  const bool origin_in_slab = o.z() >= z_lo && o.z() <= z_hi;
  // Keys packed into 48 bits in reused vectors: hash sets (OctoMap's KeySet) spend most of an
  // insertion allocating nodes.
  const auto pack = [](const octomap::OcTreeKey& k) {
    return (uint64_t(k[0]) << 32) | (uint64_t(k[1]) << 16) | uint64_t(k[2]);
  };
  const auto unpack = [](uint64_t v) {
    return octomap::OcTreeKey(octomap::key_type(v >> 32), octomap::key_type(v >> 16), octomap::key_type(v));
  };
  std::vector<uint64_t>& endpoints = m.scratch_endpoints;
  std::vector<uint64_t>& free_outside = m.scratch_free_outside;
  std::vector<uint64_t>& occupied_cells = m.scratch_occupied;
  endpoints.clear();
  free_outside.clear();
  occupied_cells.clear();
  // Each cell is updated once per insertion (occupied wins over free, as in OctoMap). Cells
  // are deduplicated on a bit grid around the origin: no hashing, no sorting. One bit per
  // cell (~75 kB for the default range and band) stays in the core's cache, where 16-bit
  // stamps that spared the clearing did not.
  const octomap::OcTreeKey ok = t.coordToKey(o);
  const int H = int(std::ceil(range / res)) + 2;
  const int kz0 = int(t.coordToKey(z_lo)) - 1, kz1 = int(t.coordToKey(z_hi)) + 1;
  const int side = 2 * H + 1, nz = std::max(1, kz1 - kz0 + 1);
  const std::size_t cells = std::size_t(side) * std::size_t(side) * std::size_t(nz);
  m.seen.assign((cells + 63) / 64, 0);
  // Sets cell i's bit; true when it was not set yet.
  const auto markNew = [](std::vector<uint64_t>& bits, long i) {
    uint64_t& word = bits[std::size_t(i) >> 6];
    const uint64_t bit = uint64_t(1) << (std::size_t(i) & 63);
    if (word & bit) return false;
    word |= bit;
    return true;
  };
  const auto local = [&](const octomap::OcTreeKey& c) -> long {
    const int x = int(c[0]) - int(ok[0]) + H, y = int(c[1]) - int(ok[1]) + H, z = int(c[2]) - kz0;
    if (x < 0 || y < 0 || z < 0 || x >= side || y >= side || z >= nz) return -1;
    return (long(z) * side + y) * side + x;  // x fastest, as the cache
  };
  std::size_t finite = 0;
  // Discretised like OctoMap's insertion: one ray per endpoint leaf, to the leaf's centre, the
  // leaves in key order. The frames gathered for an insertion hit the same leaves again and
  // again: duplicates inside the grid are dropped on its bits first, so that only the distinct
  // leaves are sorted; the few outside it are sorted on their own and merged in.
  std::vector<uint64_t>& outside_grid = m.scratch_endpoints_outside;
  outside_grid.clear();
  for (const auto& p : points) {
    if (!p.allFinite()) {
      ++bad;
      continue;
    }
    ++finite;
    octomap::OcTreeKey k;
    if (!t.coordToKeyChecked(octomap::point3d(p.x(), p.y(), p.z()), k)) continue;
    const long i = local(k);
    if (i < 0) {
      outside_grid.push_back(pack(k));
      continue;
    }
    if (markNew(m.seen, i)) endpoints.push_back(pack(k));
  }
  std::sort(endpoints.begin(), endpoints.end());
  if (!outside_grid.empty()) {
    std::sort(outside_grid.begin(), outside_grid.end());
    outside_grid.erase(std::unique(outside_grid.begin(), outside_grid.end()), outside_grid.end());
    const std::size_t inside = endpoints.size();
    endpoints.insert(endpoints.end(), outside_grid.begin(), outside_grid.end());
    std::inplace_merge(endpoints.begin(), endpoints.begin() + std::ptrdiff_t(inside), endpoints.end());
  }
  std::fill(m.seen.begin(), m.seen.end(), 0);  // the bits mark updated cells from here on
  if (skipped) *skipped += bad;
  if (finite == 0) return InsertStatus::kEmpty;
  // Ray end of each endpoint leaf (its centre, cut at the range and where it leaves the slab);
  // the endpoints that are hits inside the slab become occupied.
  const auto rayEnd = [&](const octomap::OcTreeKey& k, bool* occupied) {
    const octomap::point3d q = t.keyToCoord(k);
    const octomap::point3d d = q - o;
    const double dist = d.norm();
    const bool hit = dist <= range;
    const octomap::point3d end = hit ? q : o + d * float(range / dist);
    const bool end_in_slab = end.z() >= z_lo && end.z() <= z_hi;
    *occupied = hit && end_in_slab;
    if (end_in_slab || !origin_in_slab) return end;
    const double dz = double(end.z()) - o.z();
    const double s = (dz > 0.0 ? z_hi - o.z() : z_lo - o.z()) / dz;  // in (0, 1): leaves the slab
    return o + (end - o) * float(std::min(1.0, s + res / std::max(dist, res)));
  };
  std::vector<octomap::point3d>& ends = m.scratch_ray_ends;
  ends.resize(endpoints.size());
  for (std::size_t e = 0; e < endpoints.size(); ++e) {
    bool occ = false;
    ends[e] = rayEnd(unpack(endpoints[e]), &occ);
    if (!occ) continue;
    occupied_cells.push_back(endpoints[e]);  // sorted and unique: a subset of the endpoints
    const long i = local(unpack(endpoints[e]));
    if (i >= 0) markNew(m.seen, i);
  }
  // Traces the rays of endpoints [from, to): each cell not yet in `seen` is marked there and
  // handed to fresh(cell); cells outside the grid (origin outside the slab) go to `outside`.
  const auto trace = [&](std::size_t from, std::size_t to, std::vector<uint64_t>& seen,
                         std::vector<uint64_t>& outside, auto&& fresh) {
    for (std::size_t e = from; e < to; ++e) {
      traceRayKeys(t, o, ends[e], [&](const octomap::OcTreeKey& c) {
        const long i = local(c);
        if (i < 0) {
          outside.push_back(pack(c));  // sorted, deduplicated and applied below
          return;
        }
        if (markNew(seen, i)) fresh(c);  // else updated already (free) or to be (occupied)
      });
    }
  };
  const auto update_free = [&](const octomap::OcTreeKey& c) { m.updateLeaf(c, false); };
  // Two threads: the helper traces the second half of the rays, only gathering the cells new
  // to them, while this thread traces the first half and applies its cells; then this thread
  // applies the helper's cells that the first half did not reach, in their order. A cell is
  // updated at its first ray either way, in the same order as one thread does it: same map.
  const std::size_t split = m.params.insert_threads > 1 && endpoints.size() >= 64 ? endpoints.size() / 2 : endpoints.size();
  if (split < endpoints.size()) {
    if (!m.helper) m.helper = std::make_unique<InsertHelper>();
    m.helper_seen = m.seen;  // the occupied endpoints are not free cells for it either
    m.helper_fresh.clear();
    m.helper_free_outside.clear();
    m.helper->start([&] {
      trace(split, endpoints.size(), m.helper_seen, m.helper_free_outside,
            [&](const octomap::OcTreeKey& c) { m.helper_fresh.push_back(c); });
    });
    try {
      trace(0, split, m.seen, free_outside, update_free);
    } catch (...) {
      m.helper->wait();  // never leave the helper running on this insertion's data
      throw;
    }
    m.helper->wait();
    for (const auto& c : m.helper_fresh)
      if (markNew(m.seen, local(c))) m.updateLeaf(c, false);  // else the first half reached it first
    free_outside.insert(free_outside.end(), m.helper_free_outside.begin(), m.helper_free_outside.end());
  } else {
    trace(0, endpoints.size(), m.seen, free_outside, update_free);
  }
  std::sort(free_outside.begin(), free_outside.end());
  free_outside.erase(std::unique(free_outside.begin(), free_outside.end()), free_outside.end());
  for (const uint64_t k : free_outside)
    if (!std::binary_search(occupied_cells.begin(), occupied_cells.end(), k)) m.updateLeaf(unpack(k), false);
  for (const uint64_t k : occupied_cells) m.updateLeaf(unpack(k), true);
  m.pruneIfGrown();
  return InsertStatus::kOk;
}

void EsdfMap::setCell(const Eigen::Vector3d& p, bool occupied) {
  if (!p.allFinite()) return;
  octomap::OcTreeKey key;
  if (!impl_->tree.coordToKeyChecked(octomap::point3d(float(p.x()), float(p.y()), float(p.z())), key)) return;
  auto& t = impl_->tree;
  const float v = occupied ? t.getClampingThresMaxLog() : t.getClampingThresMinLog();
  // Setting a leaf to the value it already holds changes nothing (see Impl::cache).
  float now = 0.0f;
  const bool known = impl_->leafValue(key, &now);
  if (known && now == v) return;
  impl_->writeLeaf(key, known, now, v);
  impl_->pruneIfGrown();
}

void EsdfMap::addCylinder(double x, double y, double radius, bool occupied,
                          const std::function<bool(double, double)>& keep_column) {
  const double res = impl_->tree.getResolution();
  const double z0 = impl_->params.band_z_min;
  const double z1 = impl_->params.band_z_max;
  for (double yy = std::floor((y - radius) / res) * res + 0.5 * res; yy <= y + radius; yy += res) {
    for (double xx = std::floor((x - radius) / res) * res + 0.5 * res; xx <= x + radius; xx += res) {
      if ((xx - x) * (xx - x) + (yy - y) * (yy - y) > radius * radius) continue;
      if (keep_column && keep_column(xx, yy)) continue;
      for (double zz = std::floor(z0 / res) * res + 0.5 * res; zz <= z1 + 0.5 * res; zz += res) {
        setCell(Eigen::Vector3d(xx, yy, zz), occupied);
      }
    }
  }
}

void EsdfMap::addBox(double x0, double y0, double x1, double y1) {
  const double res = impl_->tree.getResolution();
  const double z0 = impl_->params.band_z_min;
  const double z1 = impl_->params.band_z_max;
  for (double yy = std::floor(y0 / res) * res + 0.5 * res; yy <= y1; yy += res) {
    for (double xx = std::floor(x0 / res) * res + 0.5 * res; xx <= x1; xx += res) {
      if (xx < x0 || yy < y0) continue;
      for (double zz = std::floor(z0 / res) * res + 0.5 * res; zz <= z1 + 0.5 * res; zz += res) {
        setCell(Eigen::Vector3d(xx, yy, zz), true);
      }
    }
  }
}

bool EsdfMap::isOccupied(const Eigen::Vector3d& p) const {
  auto* n = impl_->tree.search(p.x(), p.y(), p.z());
  return n && impl_->tree.isNodeOccupied(n);
}

bool EsdfMap::update(const Eigen::Vector2d& robot_xy, bool force_rebuild) {
  Impl& m = *impl_;
  Eigen::Vector2d c = robot_xy.allFinite() ? robot_xy : m.box_center;
  bool rebuilt = false;
  m.syncProjection();
  if (!m.edt || force_rebuild ||
      (c - m.box_center).cwiseAbs().maxCoeff() >= m.params.recenter_distance) {
    m.rebuild(c);
    rebuilt = true;
  } else {
    m.edt->update(true);  // only the cells changed since the last update
    ++m.incremental;
  }
  m.computeSlice(rebuilt);
  return rebuilt;
}

bool EsdfMap::ready() const { return impl_->edt != nullptr; }
double EsdfMap::helperCpuSeconds() const { return impl_->helper ? impl_->helper->cpuSeconds() : 0.0; }

double EsdfMap::distance(double x, double y, Eigen::Vector2d* grad) const {
  const Impl& m = *impl_;
  const SliceGeometry& s = m.slice;
  if (!m.edt || s.nx < 2 || s.ny < 2 || !std::isfinite(x) || !std::isfinite(y)) {
    if (grad) grad->setZero();
    return m.params.max_distance;
  }
  const double inv = 1.0 / s.resolution;
  double u = (x - s.origin.x()) * inv - 0.5;
  double v = (y - s.origin.y()) * inv - 0.5;
  bool inside_x = true, inside_y = true;
  if (u < 0.0) { u = 0.0; inside_x = false; }
  if (v < 0.0) { v = 0.0; inside_y = false; }
  if (u > s.nx - 1) { u = s.nx - 1; inside_x = false; }
  if (v > s.ny - 1) { v = s.ny - 1; inside_y = false; }
  int i0 = std::min(int(u), s.nx - 2);
  int j0 = std::min(int(v), s.ny - 2);
  const double tx = u - i0;
  const double ty = v - j0;
  const float* row0 = &m.values[std::size_t(j0) * s.nx];
  const float* row1 = row0 + s.nx;
  const double d00 = row0[i0], d10 = row0[i0 + 1], d01 = row1[i0], d11 = row1[i0 + 1];
  const double a = d00 + tx * (d10 - d00);
  const double b = d01 + tx * (d11 - d01);
  if (grad) {
    (*grad)(0) = inside_x ? ((1.0 - ty) * (d10 - d00) + ty * (d11 - d01)) * inv : 0.0;
    (*grad)(1) = inside_y ? (b - a) * inv : 0.0;
  }
  return a + ty * (b - a);
}

double EsdfMap::cellDistance(int ix, int iy) const {
  const SliceGeometry& s = impl_->slice;
  if (!s.contains(ix, iy)) return impl_->params.max_distance;
  return impl_->values[std::size_t(iy) * s.nx + ix];
}

const SliceGeometry& EsdfMap::slice() const { return impl_->slice; }
Eigen::Vector2d EsdfMap::boxCenter() const { return impl_->box_center; }
int64_t EsdfMap::incrementalUpdates() const { return impl_->incremental; }
int64_t EsdfMap::rebuilds() const { return impl_->rebuilds; }
std::size_t EsdfMap::sliceMismatches() const { return impl_->edt ? impl_->sliceMismatches() : 0; }
const MapParams& EsdfMap::params() const { return impl_->params; }

std::size_t EsdfMap::treeNodeCount() const { return impl_->tree.size(); }

void EsdfMap::pruneTree() {
  impl_->prune();
}

std::size_t EsdfMap::occupiedLeafCount() const {
  std::size_t n = 0;
  for (auto it = impl_->tree.begin_leafs(), end = impl_->tree.end_leafs(); it != end; ++it) {
    if (impl_->tree.isNodeOccupied(*it)) n += std::size_t(1) << (3 * (impl_->tree.getTreeDepth() - it.getDepth()));
  }
  return n;
}

bool EsdfMap::rayKeysMatchOctomap(const Eigen::Vector3f& origin, const Eigen::Vector3f& end,
                                  std::size_t* cells) const {
  const octomap::point3d o(origin.x(), origin.y(), origin.z()), e(end.x(), end.y(), end.z());
  octomap::KeyRay ray;
  const bool ok_octomap = impl_->tree.computeRayKeys(o, e, ray);
  std::vector<octomap::OcTreeKey> mine;
  const bool ok_mine = traceRayKeys(impl_->tree, o, e, [&](const octomap::OcTreeKey& k) { mine.push_back(k); });
  if (cells) *cells = mine.size();
  if (ok_octomap != ok_mine) return false;
  if (!ok_octomap) return true;
  return std::equal(ray.begin(), ray.end(), mine.begin(), mine.end());
}

}  // namespace ucon::planner
