#include "ucon/perception/reassociation.hpp"

#include <algorithm>

#include "ucon/perception/footprint.hpp"

namespace ucon {
namespace perception {

std::vector<std::vector<int>> reassociate(const std::vector<HistoricalObject>& objects,
                                          const ProximityIndex& index, double d0, double gamma) {
  std::vector<std::vector<int>> result(objects.size());
  if (index.size() == 0) return result;
  std::vector<char> taken(static_cast<std::size_t>(index.size()), 0);
  const float d0_sq = static_cast<float>(d0 * d0);
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const HistoricalObject& obj = objects[k];
    const int n_c = static_cast<int>(obj.points.size());
    if (n_c == 0 || !obj.velocity.allFinite() || !(obj.tau >= 0.0)) continue;
    const Eigen::Vector3f shift = (obj.velocity * obj.tau).cast<float>();
    int n = 0;
    std::vector<int> p_c;
    for (const auto& p : obj.points) {
      float d2 = 0.0f;
      // Querying at p + v tau finds the q that minimises |p + v tau - q| directly.
      const int q = index.nearestWithin(p + shift, d0_sq, &d2);
      if (q < 0) continue;
      ++n;
      p_c.push_back(q);
    }
    if (static_cast<double>(n) <= gamma * static_cast<double>(n_c)) continue;
    std::sort(p_c.begin(), p_c.end());
    p_c.erase(std::unique(p_c.begin(), p_c.end()), p_c.end());
    std::vector<int> mine;
    for (int q : p_c) {
      if (taken[q]) continue;
      taken[q] = 1;
      mine.push_back(q);
    }
    result[k] = std::move(mine);
  }
  return result;
}

Recovery recoverLostTracks(const std::vector<LostTrack>& lost, const Points& points, const ProximityIndex& index,
                           const std::vector<const std::vector<int>*>& matched, const Eigen::Vector2d& sensor_xy,
                           const PerceptionParams& params) {
  Recovery r;
  r.points.resize(lost.size());
  r.claimed.assign(points.size(), 0);
  std::vector<HistoricalObject> objects;
  objects.reserve(lost.size());
  for (const auto& l : lost) objects.push_back(l.history);
  const auto rec = reassociate(objects, index, params.paper.d0, params.paper.gamma);
  for (const auto& pc : rec)
    for (int i : pc) r.claimed[i] = 1;
  // A point measured by an object-level match stays with it: re-association recovers objects
  // the matching lost, it does not split the clusters it matched.
  for (const auto* m : matched)
    for (int i : *m) r.claimed[i] = 0;
  for (std::size_t k = 0; k < lost.size(); ++k) {
    std::vector<int> mine;
    for (int i : rec[k])
      if (r.claimed[i]) mine.push_back(i);
    if (mine.size() < 2) continue;  // what the matches left is too little to measure
    // Points centred away from the prediction belong to something else (typically the
    // occluder in front of a hidden object): not a recovery.
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int i : mine) c += points[i].head<2>().cast<double>();
    c /= static_cast<double>(mine.size());
    if ((c - lost[k].view.box.center).norm() > params.reassociation.max_shift) continue;
    // Nor a neighbour on the next line (see passesCrossGate), judged by the view-corrected
    // centre, as object-level association judges a cluster.
    const Eigen::Vector2d view_c = viewCorrectedCenter(points, mine, sensor_xy, params.segmentation.view_center_shift);
    if (!passesCrossGate(view_c, lost[k].view, params.object_association)) continue;
    r.points[k] = std::move(mine);
  }
  return r;
}

bool mostlyClaimed(const std::vector<int>& indices, const std::vector<char>& claimed) {
  const auto taken = std::count_if(indices.begin(), indices.end(), [&](int p) { return claimed[p] != 0; });
  return 2 * taken >= static_cast<long>(indices.size());
}

}  // namespace perception
}  // namespace ucon
