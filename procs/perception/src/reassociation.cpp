#include "ucon/perception/reassociation.hpp"

#include <algorithm>

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

}  // namespace perception
}  // namespace ucon
