#include "ucon/lio/voxel_map.hpp"

#include <tsl/robin_map.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace ucon {
namespace lio {

namespace {

constexpr int kBits = 21;
constexpr uint64_t kMask = (uint64_t{1} << kBits) - 1;

uint64_t packKey(int32_t x, int32_t y, int32_t z) {
  return ((static_cast<uint64_t>(x) & kMask) << (2 * kBits)) | ((static_cast<uint64_t>(y) & kMask) << kBits) |
         (static_cast<uint64_t>(z) & kMask);
}

// Sign-extends a kBits-wide field.
int32_t field(uint64_t key, int shift) {
  const int64_t v = static_cast<int64_t>((key >> shift) & kMask);
  return static_cast<int32_t>(v >= (int64_t{1} << (kBits - 1)) ? v - (int64_t{1} << kBits) : v);
}

// splitmix64's finaliser: neighbouring keys land in unrelated buckets (the identity hash of
// std::hash<uint64_t> would pile them into a few runs of robin_map's power-of-two table).
struct KeyHash {
  std::size_t operator()(uint64_t k) const {
    k ^= k >> 30;
    k *= 0xbf58476d1ce4e5b9ULL;
    k ^= k >> 27;
    k *= 0x94d049bb133111ebULL;
    k ^= k >> 31;
    return static_cast<std::size_t>(k);
  }
};

// floor() for the finite values of a map (|x| far below 2^31): a truncation and a correction,
// without the library call that baseline x86-64 makes for std::floor.
int32_t floorToInt(float x) {
  const int32_t i = static_cast<int32_t>(x);
  return static_cast<float>(i) > x ? i - 1 : i;
}

// An array that grows by fixed chunks of kChunk items and never moves what it holds. A
// std::vector doubles: it copies itself into a block twice its size, so the process's resident
// memory jumps by the whole store each time the map crosses a power of two (and the pages of
// the old block may stay resident). Here the map grows by one chunk at a time. An item is
// `width` consecutive values of T, default-initialised: floats are left as they are (their pages
// are not touched until points are written), a Slot takes its member initialisers.
template <typename T>
class ChunkedArray {
 public:
  static constexpr int kShift = 8;
  static constexpr std::size_t kChunk = std::size_t{1} << kShift;

  explicit ChunkedArray(std::size_t width = 1) : width_(width) {}
  T* item(std::size_t i) { return chunks_[i >> kShift].get() + (i & (kChunk - 1)) * width_; }
  const T* item(std::size_t i) const { return chunks_[i >> kShift].get() + (i & (kChunk - 1)) * width_; }
  T& operator[](std::size_t i) { return *item(i); }
  const T& operator[](std::size_t i) const { return *item(i); }
  std::size_t size() const { return size_; }
  void setWidth(std::size_t width) { width_ = width; }
  /// Appends one item.
  void grow() {
    if (size_ == chunks_.size() * kChunk) chunks_.emplace_back(new T[kChunk * width_]);
    ++size_;
  }

 private:
  std::size_t width_;
  std::size_t size_ = 0;
  std::vector<std::unique_ptr<T[]>> chunks_;
};

}  // namespace

struct VoxelMap::Impl {
  struct Slot {
    uint64_t key = 0;
    int32_t prev = -1, next = -1;  // LRU list: head = most recently updated
    int32_t misses = 0;            // carve(): seen through since the last insert() touched it
    int32_t count = 0;             // points held; 0 for a free slot
    double sum[3] = {0.0, 0.0, 0.0};  // of the points, in insertion order (carve()'s centroid)
  };
  // The index's value: the voxel's slot and its point count, so that a query reads the count
  // from the bucket it has just loaded instead of from another cache line.
  struct Entry {
    int32_t slot;
    int32_t count;
  };

  tsl::robin_map<uint64_t, Entry, KeyHash> index;
  ChunkedArray<Slot> slots;
  // A slot's points in one block of 3 * cap floats, x then y then z (structure of arrays inside
  // the block), so that the distances to a voxel's points are computed several at a time and a
  // query touches one contiguous run of memory per voxel.
  ChunkedArray<float> pts;
  std::vector<int32_t> free_slots;
  int32_t head = -1, tail = -1;
  std::size_t num_points = 0;
  int cap = 20;
  float voxel = 0.5f, inv_voxel = 2.0f, spacing2 = 0.01f;
  int64_t max_voxels = 200000;
  std::vector<Eigen::Vector3i> offsets;  // own voxel first
  // carve()'s scratch, kept between calls: the range image and the voxels to drop.
  std::vector<float> range_image;
  std::vector<int32_t> doomed;

  float* block(int32_t s) { return pts.item(static_cast<std::size_t>(s)); }
  const float* block(int32_t s) const { return pts.item(static_cast<std::size_t>(s)); }
  void unlink(int32_t s) {
    Slot& sl = slots[static_cast<std::size_t>(s)];
    if (sl.prev >= 0) slots[static_cast<std::size_t>(sl.prev)].next = sl.next; else head = sl.next;
    if (sl.next >= 0) slots[static_cast<std::size_t>(sl.next)].prev = sl.prev; else tail = sl.prev;
    sl.prev = sl.next = -1;
  }
  void pushFront(int32_t s) {
    Slot& sl = slots[static_cast<std::size_t>(s)];
    sl.prev = -1;
    sl.next = head;
    if (head >= 0) slots[static_cast<std::size_t>(head)].prev = s;
    head = s;
    if (tail < 0) tail = s;
  }
  void drop(int32_t s) {
    Slot& sl = slots[static_cast<std::size_t>(s)];
    const auto it = index.find(sl.key);
    num_points -= static_cast<std::size_t>(it->second.count);
    index.erase(it);
    unlink(s);
    sl.count = 0;
    free_slots.push_back(s);
  }
  // A new, empty voxel for `key` (evicting the least recently updated one beyond max_voxels).
  tsl::robin_map<uint64_t, Entry, KeyHash>::iterator allocate(uint64_t key) {
    if (static_cast<int64_t>(index.size()) >= max_voxels && tail >= 0) drop(tail);
    int32_t s;
    if (!free_slots.empty()) {
      s = free_slots.back();
      free_slots.pop_back();
    } else {
      s = static_cast<int32_t>(slots.size());
      slots.grow();
      pts.grow();
    }
    Slot& sl = slots[static_cast<std::size_t>(s)];
    sl.key = key;
    sl.misses = 0;
    sl.count = 0;
    sl.sum[0] = sl.sum[1] = sl.sum[2] = 0.0;
    pushFront(s);
    return index.emplace(key, Entry{s, 0}).first;
  }
  uint64_t keyOf(const Eigen::Vector3f& p, Eigen::Vector3i* cell) const {
    const Eigen::Vector3i c(floorToInt(p.x() * inv_voxel), floorToInt(p.y() * inv_voxel),
                            floorToInt(p.z() * inv_voxel));
    if (cell) *cell = c;
    return packKey(c.x(), c.y(), c.z());
  }
};

VoxelMap::VoxelMap(const VoxelMapParams& params) : params_(params), impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.cap = std::max(1, std::min(64, params.max_points_per_voxel));
  m.pts.setWidth(static_cast<std::size_t>(3 * m.cap));
  m.voxel = static_cast<float>(params.voxel_size > 0.0 ? params.voxel_size : 0.5);
  m.inv_voxel = 1.0f / m.voxel;
  m.spacing2 = static_cast<float>(params.min_point_spacing * params.min_point_spacing);
  m.max_voxels = std::max<int64_t>(1, params.max_voxels);
  m.offsets.emplace_back(0, 0, 0);
  for (int axis = 0; axis < 3; ++axis)
    for (int s : {-1, 1}) {
      Eigen::Vector3i o = Eigen::Vector3i::Zero();
      o[axis] = s;
      m.offsets.push_back(o);
    }
  if (params.neighbourhood != Neighbourhood::kFaces) {
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nz = (dx != 0) + (dy != 0) + (dz != 0);
          if (nz == 2 || (nz == 3 && params.neighbourhood == Neighbourhood::kAll)) m.offsets.emplace_back(dx, dy, dz);
        }
  }
}

VoxelMap::~VoxelMap() = default;
VoxelMap::VoxelMap(VoxelMap&&) noexcept = default;
VoxelMap& VoxelMap::operator=(VoxelMap&&) noexcept = default;

bool VoxelMap::insert(const Eigen::Vector3f& p) {
  if (!p.allFinite()) return false;
  Impl& m = *impl_;
  const uint64_t key = m.keyOf(p, nullptr);
  auto it = m.index.find(key);
  if (it == m.index.end()) {
    it = m.allocate(key);
  } else if (m.head != it->second.slot) {
    m.unlink(it->second.slot);
    m.pushFront(it->second.slot);
  }
  Impl::Slot& slot = m.slots[static_cast<std::size_t>(it->second.slot)];
  slot.misses = 0;
  const int count = it->second.count;
  if (count >= m.cap) return false;
  float* xs = m.block(it->second.slot);
  float* ys = xs + m.cap;
  float* zs = ys + m.cap;
  for (int i = 0; i < count; ++i) {
    const float dx = xs[i] - p.x(), dy = ys[i] - p.y(), dz = zs[i] - p.z();
    if (dx * dx + dy * dy + dz * dz < m.spacing2) return false;
  }
  xs[count] = p.x();
  ys[count] = p.y();
  zs[count] = p.z();
  it.value().count = count + 1;
  slot.count = count + 1;
  slot.sum[0] += static_cast<double>(p.x());
  slot.sum[1] += static_cast<double>(p.y());
  slot.sum[2] += static_cast<double>(p.z());
  ++m.num_points;
  return true;
}

std::size_t VoxelMap::insert(const std::vector<Eigen::Vector3f>& points) {
  std::size_t n = 0;
  for (const auto& p : points) n += insert(p) ? 1 : 0;
  return n;
}

int VoxelMap::nearest(const Eigen::Vector3f& q, int k, float max_distance, Neighbours* out) const {
  out->count = 0;
  if (!q.allFinite() || k <= 0) return 0;
  k = std::min(k, Neighbours::kMax);
  const Impl& m = *impl_;
  Eigen::Vector3i c;
  m.keyOf(q, &c);
  const float max2 = max_distance * max_distance;
  // Position of q inside its voxel, for the distance to a neighbour voxel's nearest face.
  const Eigen::Vector3f lo = c.cast<float>() * m.voxel;
  const Eigen::Vector3f in = q - lo;
  // The k best so far, ascending: distances and where each point's x lies (y and z follow at
  // +cap and +2 cap), kept locally so that an insertion moves two words; copied out at the end.
  float best_d2[Neighbours::kMax];
  const float* best_at[Neighbours::kMax];
  int n = 0;
  for (const Eigen::Vector3i& o : m.offsets) {
    // Lower bound of the squared distance from q to any point of that voxel: skip it when it
    // cannot beat the current k-th neighbour (the own voxel is searched first).
    float bound = 0.0f;
    for (int a = 0; a < 3; ++a) {
      const float d = o[a] < 0 ? in[a] : o[a] > 0 ? m.voxel - in[a] : 0.0f;
      bound += d * d;
    }
    if (bound >= max2 || (n == k && bound >= best_d2[k - 1])) continue;
    const Eigen::Vector3i cc = c + o;
    const auto it = m.index.find(packKey(cc.x(), cc.y(), cc.z()));
    if (it == m.index.end()) continue;
    const int count = it->second.count;
    const float* xs = m.block(it->second.slot);
    const float* ys = xs + m.cap;
    const float* zs = ys + m.cap;
    // All distances first, counting those that could enter (below max_distance and, once k
    // are held, below the k-th): a loop the compiler vectorises. The sorted insertion runs
    // only over a voxel that has such a point.
    const float limit0 = n == k ? best_d2[k - 1] : max2;
    float d2s[64];
    int below = 0;
    for (int i = 0; i < count; ++i) {
      const float dx = xs[i] - q.x(), dy = ys[i] - q.y(), dz = zs[i] - q.z();
      const float d2 = dx * dx + dy * dy + dz * dz;
      d2s[i] = d2;
      below += d2 < limit0 ? 1 : 0;
    }
    if (below == 0) continue;
    float limit = limit0;
    for (int i = 0; i < count; ++i) {
      const float d2 = d2s[i];
      if (!(d2 < limit)) continue;
      // Insertion into the sorted list (strict '<': an equal distance keeps the earlier point).
      int j = n < k ? n++ : k - 1;
      while (j > 0 && best_d2[j - 1] > d2) {
        best_d2[j] = best_d2[j - 1];
        best_at[j] = best_at[j - 1];
        --j;
      }
      best_d2[j] = d2;
      best_at[j] = xs + i;
      if (n == k) limit = best_d2[k - 1];
    }
  }
  const std::size_t cap = static_cast<std::size_t>(m.cap);
  for (int j = 0; j < n; ++j) {
    out->dist2[j] = best_d2[j];
    out->points[j] = Eigen::Vector3f(best_at[j][0], best_at[j][cap], best_at[j][2 * cap]);
  }
  out->count = n;
  return n;
}

std::size_t VoxelMap::carve(const Eigen::Vector3d& origin, const Eigen::Matrix3d& R,
                            const std::vector<Eigen::Vector3f>& points) {
  Impl& m = *impl_;
  constexpr double kPi = 3.14159265358979323846;
  const double bin = params_.carve_bin_deg * kPi / 180.0;
  if (!(bin > 0.0) || !(params_.carve_radius > 0.0) || !origin.allFinite() || !R.allFinite()) return 0;
  // Range image over azimuth [-pi, pi) and elevation [-pi/2, pi/2]: the nearest return per bin.
  const int n_az = std::max(1, static_cast<int>(std::ceil(2.0 * kPi / bin)));
  const int n_el = std::max(1, static_cast<int>(std::ceil(kPi / bin)));
  std::vector<float>& nearest = m.range_image;
  nearest.assign(static_cast<std::size_t>(n_az) * static_cast<std::size_t>(n_el),
                 std::numeric_limits<float>::infinity());
  auto binOf = [&](double x, double y, double z, double r) {
    const int a = std::clamp(static_cast<int>((std::atan2(y, x) + kPi) / bin), 0, n_az - 1);
    const int e = std::clamp(static_cast<int>((std::asin(std::clamp(z / r, -1.0, 1.0)) + 0.5 * kPi) / bin), 0,
                             n_el - 1);
    return static_cast<std::size_t>(e) * static_cast<std::size_t>(n_az) + static_cast<std::size_t>(a);
  };
  for (const Eigen::Vector3f& p : points) {
    if (!p.allFinite()) continue;
    const double r = p.cast<double>().norm();
    if (!(r > 1e-3)) continue;
    float& b = nearest[binOf(p.x(), p.y(), p.z(), r)];
    b = std::min(b, static_cast<float>(r));
  }
  // Every voxel, in slot order (one pass over contiguous memory; which voxels go does not
  // depend on the order); the key's cell gives a cheap distance test before the centroid.
  const Eigen::Matrix3d Rt = R.transpose();
  const double rad = params_.carve_radius, margin = params_.carve_margin;
  const double tan_bin = std::tan(bin);
  const double reach = rad + m.voxel, dz_max = std::min(rad, 3.0) + m.voxel;
  std::vector<int32_t>& doomed = m.doomed;
  doomed.clear();
  const int32_t n_slots = static_cast<int32_t>(m.slots.size());
  for (int32_t s = 0; s < n_slots; ++s) {
    const Impl::Slot& sl = m.slots[static_cast<std::size_t>(s)];
    const int count = sl.count;
    if (count <= 0) continue;
    const Eigen::Vector3d vc((field(sl.key, 2 * kBits) + 0.5) * m.voxel, (field(sl.key, kBits) + 0.5) * m.voxel,
                             (field(sl.key, 0) + 0.5) * m.voxel);
    if ((vc - origin).squaredNorm() > reach * reach || std::fabs(vc.z() - origin.z()) > dz_max) continue;
    const Eigen::Vector3d c(sl.sum[0], sl.sum[1], sl.sum[2]);
    const Eigen::Vector3d d = Rt * (c / count - origin);
    const double r = d.norm();
    if (!(r > 1e-3) || r > rad) continue;
    const float seen = nearest[binOf(d.x(), d.y(), d.z(), r)];
    // No ray there, or one ended at or before it (within the margin plus the bin's width
    // there: a coarse bin at a grazing angle holds returns from both sides of the centroid).
    if (!std::isfinite(seen) || seen <= r + margin + r * tan_bin) continue;
    if (++m.slots[static_cast<std::size_t>(s)].misses >= params_.carve_misses) doomed.push_back(s);
  }
  for (int32_t s : doomed) m.drop(s);
  return doomed.size();
}

std::size_t VoxelMap::removeFar(const Eigen::Vector3d& center) {
  Impl& m = *impl_;
  const double r2 = params_.radius * params_.radius;
  std::size_t dropped = 0;
  for (int32_t s = m.head; s >= 0;) {
    const Impl::Slot& sl = m.slots[static_cast<std::size_t>(s)];
    const int32_t next = sl.next;
    const Eigen::Vector3d vc((field(sl.key, 2 * kBits) + 0.5) * m.voxel, (field(sl.key, kBits) + 0.5) * m.voxel,
                             (field(sl.key, 0) + 0.5) * m.voxel);
    if ((vc - center).squaredNorm() > r2) {
      m.drop(s);
      ++dropped;
    }
    s = next;
  }
  return dropped;
}

void VoxelMap::clear() {
  const VoxelMapParams p = params_;
  *this = VoxelMap(p);
}

std::size_t VoxelMap::numVoxels() const { return impl_->index.size(); }
std::size_t VoxelMap::numPoints() const { return impl_->num_points; }

std::vector<Eigen::Vector3f> VoxelMap::points() const {
  const Impl& m = *impl_;
  std::vector<Eigen::Vector3f> out;
  out.reserve(m.num_points);
  for (int32_t s = m.head; s >= 0; s = m.slots[static_cast<std::size_t>(s)].next) {
    const auto& sl = m.slots[static_cast<std::size_t>(s)];
    const float* xs = m.block(s);
    const int count = m.index.find(sl.key)->second.count;
    for (int i = 0; i < count; ++i) out.emplace_back(xs[i], xs[m.cap + i], xs[2 * m.cap + i]);
  }
  return out;
}

}  // namespace lio
}  // namespace ucon
