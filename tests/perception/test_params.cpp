// One source of truth for perception's parameters: deploy/config/perception.yaml loads into
// exactly the in-class defaults of PerceptionParams, key by key, and holds no key this test
// does not compare.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "ucon/config.hpp"
#include "ucon/perception/params.hpp"

using ucon::perception::PerceptionParams;

namespace {

const char* const kShipped = "deploy/config/perception.yaml";  // tests run from the source root

std::string shippedText() {
  std::ifstream f(kShipped);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Every key of perception.yaml as the field it loads into; the field path is the dotted key.
#define UCON_PERCEPTION_KEYS(X)                                                                    \
  X(paper.mu) X(paper.d0) X(paper.gamma)                                                           \
  X(association) X(pose_max_gap) X(frame_timeout)                                                  \
  X(preprocess.min_range) X(preprocess.max_range) X(preprocess.min_height)                         \
  X(preprocess.max_height) X(preprocess.accumulate_frames) X(preprocess.voxel_size)                \
  X(preprocess.sensor_origin)                                                                      \
  X(segmentation.cluster_tolerance) X(segmentation.min_cluster_points)                             \
  X(segmentation.max_cluster_points) X(segmentation.far_cluster_range)                             \
  X(segmentation.far_cluster_tolerance) X(segmentation.max_object_size)                            \
  X(segmentation.min_object_height) X(segmentation.history_min_age)                                \
  X(segmentation.history_max_age) X(segmentation.history_chunk) X(segmentation.motion_distance)    \
  X(segmentation.motion_distance_per_m) X(segmentation.motion_ratio)                               \
  X(segmentation.free_space_bin_deg) X(segmentation.free_space_margin)                             \
  X(segmentation.track_support_distance) X(segmentation.vanish_max_gap)                            \
  X(segmentation.free_memory) X(segmentation.free_memory_heights) X(segmentation.free_memory_cell)  \
  X(segmentation.free_memory_range)                                                                \
  X(segmentation.history_static_only) X(segmentation.split_max_size)                               \
  X(segmentation.view_center_shift) X(segmentation.occlusion_anchor)                               \
  X(segmentation.occlusion_margin) X(segmentation.static_persistence)                              \
  X(segmentation.static_cell) X(segmentation.static_max_gap)                                       \
  X(segmentation.static_hold_max)                                                                  \
  X(object_association.cost_gate) X(object_association.max_distance)                               \
  X(object_association.distance_growth) X(object_association.max_distance_cap)                     \
  X(object_association.direction_min_speed) X(object_association.fapp_gate)                        \
  X(object_association.gate_sigma) X(object_association.distance_weight)                           \
  X(object_association.centroid_std) X(object_association.cross_gate)                              \
  X(object_association.cross_gate_growth) X(object_association.cross_gate_after)                   \
  X(object_association.cross_gate_until) X(object_association.cross_rank_weight)                   \
  X(object_association.size_floor) X(object_association.cascade_after) X(object_association.split_shared)                             \
  X(reassociation.enabled) X(reassociation.max_history_points) X(reassociation.max_shift)          \
  X(reassociation.max_consecutive)                                                                 \
  X(tracks.confirm_hits) X(tracks.confirm_min_speed) X(tracks.confirm_max_speed)                   \
  X(tracks.confirm_min_distance) X(tracks.confirm_moving_hits) X(tracks.max_stationary)            \
  X(tracks.structure_share) X(tracks.structure_margin) X(tracks.structure_frames)                  \
  X(tracks.structure_arrival_distance) X(tracks.structure_decline)                                                             \
  X(tracks.new_track_separation) X(tracks.reid_speed) X(tracks.reid_margin) X(tracks.reid_window)  \
  X(tracks.reid_cross_speed) X(tracks.reid_confirm) X(tracks.reid_velocity) X(tracks.merge_margin)  \
  X(tracks.tentative_max_age)                                                                      \
  X(tracks.tentative_max_misses) X(tracks.max_coast) X(tracks.coast_velocity_decay)                \
  X(tracks.free_bin_deg) X(tracks.free_margin) X(tracks.free_frames) X(tracks.velocity_baseline)   \
  X(tracks.registration_velocity) X(tracks.size_smoothing)                                         \
  X(kalman.accel_psd_xy) X(kalman.accel_psd_z) X(kalman.position_std) X(kalman.velocity_std)       \
  X(kalman.initial_velocity_std)

// Leaf keys of a YAML mapping, dotted.
void leafKeys(const YAML::Node& n, const std::string& prefix, std::set<std::string>* out) {
  for (const auto& kv : n) {
    const std::string key = prefix.empty() ? kv.first.as<std::string>() : prefix + "." + kv.first.as<std::string>();
    if (kv.second.IsMap()) {
      leafKeys(kv.second, key, out);
    } else {
      out->insert(key);
    }
  }
}

}  // namespace

TEST(PerceptionParams, GivenTheShippedConfigThenEveryKeyEqualsItsInClassDefault) {
  const std::string text = shippedText();
  ASSERT_FALSE(text.empty()) << kShipped << " not found";
  std::vector<ucon::ConfigError> errors;
  const auto shipped = ucon::loadParams<PerceptionParams>(text, kShipped, &errors);
  ASSERT_TRUE(shipped.has_value()) << (errors.empty() ? "" : errors[0].toString());
  const PerceptionParams defaults;
#define UCON_EXPECT_KEY(field) \
  EXPECT_EQ(shipped->field, defaults.field) << #field << ": " << kShipped << " and the in-class default differ";
  UCON_PERCEPTION_KEYS(UCON_EXPECT_KEY)
#undef UCON_EXPECT_KEY
}

TEST(PerceptionParams, GivenTheShippedConfigThenTheDefaultsTestCoversEachOfItsKeys) {
  const std::set<std::string> compared{
#define UCON_KEY_NAME(field) #field,
      UCON_PERCEPTION_KEYS(UCON_KEY_NAME)
#undef UCON_KEY_NAME
  };
  std::set<std::string> in_file;
  leafKeys(YAML::LoadFile(kShipped), "", &in_file);
  for (const auto& k : in_file) EXPECT_TRUE(compared.count(k)) << k << ": add it to UCON_PERCEPTION_KEYS";
  for (const auto& k : compared) EXPECT_TRUE(in_file.count(k)) << k << ": not in " << kShipped;
}

namespace {
// The keys the loader names when `from` in the shipped file is replaced by `to`.
std::vector<std::string> errorKeysWith(const std::string& from, const std::string& to) {
  std::string text = shippedText();
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at == std::string::npos) return {};
  text.replace(at, from.size(), to);
  std::vector<ucon::ConfigError> errors;
  EXPECT_FALSE(ucon::loadParams<PerceptionParams>(text, kShipped, &errors).has_value());
  std::vector<std::string> keys;
  for (const auto& e : errors) keys.push_back(e.key);
  return keys;
}
}  // namespace

TEST(PerceptionParams, GivenABadValueThenLoadingFailsNamingItsKey) {
  EXPECT_EQ(errorKeysWith("  gamma: 0.35", "  gamma: 1.5"), std::vector<std::string>{"paper.gamma"});
}

TEST(PerceptionParams, GivenTheFreeMemoryBandUpsideDownThenLoadingFailsNamingItsKey) {
  EXPECT_EQ(errorKeysWith("free_memory_heights: [0.2, 0.6]", "free_memory_heights: [0.6, 0.2]"),
            std::vector<std::string>{"segmentation.free_memory_heights"});
}
