#include "ray_insertion.hpp"

#include <condition_variable>
#include <exception>
#include <functional>
#include <iterator>
#include <mutex>
#include <thread>
#include <utility>

#include "ucon/cpu_time.hpp"

namespace ucon::planner {

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

RayInsertion::RayInsertion(const MapParams& params) : params_(params) {}
RayInsertion::~RayInsertion() = default;

double RayInsertion::helperCpuSeconds() const { return helper_ ? helper_->cpuSeconds() : 0.0; }

InsertStatus RayInsertion::insert(LeafCache& leaves, const Eigen::Vector3d& origin,
                                  const std::vector<Eigen::Vector3f>& points, double range, int64_t* skipped) {
  const octomap::point3d o(float(origin.x()), float(origin.y()), float(origin.z()));
  return params_.band_only ? insertBand(leaves, o, points, range, skipped)
                           : insertAllHeights(leaves, o, points, range, skipped);
}

InsertStatus RayInsertion::insertAllHeights(LeafCache& leaves, const octomap::point3d& o,
                                            const std::vector<Eigen::Vector3f>& points, double range,
                                            int64_t* skipped) {
  int64_t bad = 0;
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
  leaves.tree().insertPointCloud(cloud, o, range, /*lazy_eval=*/false, /*discretize=*/true);
  leaves.forget();  // unknown which leaves changed; insertPointCloud prunes
  return InsertStatus::kOk;
}

// The same update as OctoMap's discretised insertPointCloud, restricted to the height band:
// each ray is traced only until it leaves the band's slab (one leaf of margin), because the
// cells beyond cannot change the band. The band's cells get exactly the updates of a full
// insertion (a clipped ray visits a prefix of the full ray's cells), at a fraction of the
// work: the sensor sits in the band and most returns lie above it.
InsertStatus RayInsertion::insertBand(LeafCache& leaves, const octomap::point3d& o,
                                      const std::vector<Eigen::Vector3f>& points, double range,
                                      int64_t* skipped) {
  int64_t bad = 0;
  const octomap::OcTree& t = leaves.tree();
  const double res = t.getResolution();
  const double z_lo = t.keyToCoord(leaves.bandKeyMin()) - 1.5 * res;
  const double z_hi = t.keyToCoord(leaves.bandKeyMax()) + 1.5 * res;
  const bool origin_in_slab = o.z() >= z_lo && o.z() <= z_hi;
  // Keys packed into 48 bits in reused vectors: hash sets (OctoMap's KeySet) spend most of an
  // insertion allocating nodes.
  const auto pack = [](const octomap::OcTreeKey& k) {
    return (uint64_t(k[0]) << 32) | (uint64_t(k[1]) << 16) | uint64_t(k[2]);
  };
  const auto unpack = [](uint64_t v) {
    return octomap::OcTreeKey(octomap::key_type(v >> 32), octomap::key_type(v >> 16), octomap::key_type(v));
  };
  std::vector<uint64_t>& endpoints = endpoints_;
  std::vector<uint64_t>& free_outside = free_outside_;
  std::vector<uint64_t>& occupied_cells = occupied_;
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
  seen_.assign((cells + 63) / 64, 0);
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
  std::vector<uint64_t>& outside_grid = endpoints_outside_;
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
    if (markNew(seen_, i)) endpoints.push_back(pack(k));
  }
  std::sort(endpoints.begin(), endpoints.end());
  if (!outside_grid.empty()) {
    std::sort(outside_grid.begin(), outside_grid.end());
    outside_grid.erase(std::unique(outside_grid.begin(), outside_grid.end()), outside_grid.end());
    const std::size_t inside = endpoints.size();
    endpoints.insert(endpoints.end(), outside_grid.begin(), outside_grid.end());
    std::inplace_merge(endpoints.begin(), endpoints.begin() + std::ptrdiff_t(inside), endpoints.end());
  }
  std::fill(seen_.begin(), seen_.end(), 0);  // the bits mark updated cells from here on
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
  std::vector<octomap::point3d>& ends = ray_ends_;
  ends.resize(endpoints.size());
  for (std::size_t e = 0; e < endpoints.size(); ++e) {
    bool occ = false;
    ends[e] = rayEnd(unpack(endpoints[e]), &occ);
    if (!occ) continue;
    occupied_cells.push_back(endpoints[e]);  // sorted and unique: a subset of the endpoints
    const long i = local(unpack(endpoints[e]));
    if (i >= 0) markNew(seen_, i);
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
  const auto update_free = [&](const octomap::OcTreeKey& c) { leaves.updateLeaf(c, false); };
  // Two threads: the helper traces the second half of the rays, only gathering the cells new
  // to them, while this thread traces the first half and applies its cells; then this thread
  // applies the helper's cells that the first half did not reach, in their order. A cell is
  // updated at its first ray either way, in the same order as one thread does it: same map.
  const std::size_t split = params_.insert_threads > 1 && endpoints.size() >= 64 ? endpoints.size() / 2 : endpoints.size();
  if (split < endpoints.size()) {
    if (!helper_) helper_ = std::make_unique<InsertHelper>();
    helper_seen_ = seen_;  // the occupied endpoints are not free cells for it either
    helper_fresh_.clear();
    helper_free_outside_.clear();
    helper_->start([&] {
      trace(split, endpoints.size(), helper_seen_, helper_free_outside_,
            [&](const octomap::OcTreeKey& c) { helper_fresh_.push_back(c); });
    });
    try {
      trace(0, split, seen_, free_outside, update_free);
    } catch (...) {
      helper_->wait();  // never leave the helper running on this insertion's data
      throw;
    }
    helper_->wait();
    for (const auto& c : helper_fresh_)
      if (markNew(seen_, local(c))) leaves.updateLeaf(c, false);  // else the first half reached it first
    free_outside.insert(free_outside.end(), helper_free_outside_.begin(), helper_free_outside_.end());
  } else {
    trace(0, endpoints.size(), seen_, free_outside, update_free);
  }
  std::sort(free_outside.begin(), free_outside.end());
  free_outside.erase(std::unique(free_outside.begin(), free_outside.end()), free_outside.end());
  for (const uint64_t k : free_outside)
    if (!std::binary_search(occupied_cells.begin(), occupied_cells.end(), k)) leaves.updateLeaf(unpack(k), false);
  for (const uint64_t k : occupied_cells) leaves.updateLeaf(unpack(k), true);
  leaves.pruneIfGrown();
  return InsertStatus::kOk;
}

}  // namespace ucon::planner
