#include "ucon/perception/params.hpp"

#include "ucon/config.hpp"

namespace ucon {
namespace perception {

void PaperParams::read(ConfigReader& r) {
  r.read("mu", mu, 3, 0.0, 100.0);
  r.read("d0", d0, 1e-3, 10.0);
  r.read("gamma", gamma, 1e-3, 0.999);
}

void PreprocessParams::read(ConfigReader& r) {
  r.read("min_range", min_range, 0.0, 10.0);
  r.read("max_range", max_range, 0.1, 200.0);
  r.read("min_height", min_height, -10.0, 10.0);
  r.read("max_height", max_height, -10.0, 20.0);
  r.read("accumulate_frames", accumulate_frames, 1, 10);
  r.read("voxel_size", voxel_size, 0.005, 1.0);
  r.read("sensor_origin", sensor_origin, 3, -10.0, 10.0);
  if (max_range <= min_range) r.fail("max_range", "must be greater than min_range");
  if (max_height <= min_height) r.fail("max_height", "must be greater than min_height");
}

void SegmentationParams::read(ConfigReader& r) {
  r.read("cluster_tolerance", cluster_tolerance, 0.01, 5.0);
  r.read("min_cluster_points", min_cluster_points, 1, 100000);
  r.read("max_cluster_points", max_cluster_points, 1, 10000000);
  r.read("far_cluster_range", far_cluster_range, 0.0, 100.0);
  r.read("far_cluster_tolerance", far_cluster_tolerance, 0.0, 5.0);
  r.read("max_object_size", max_object_size, 0.05, 20.0);
  r.read("min_object_height", min_object_height, 0.0, 10.0);
  r.read("history_min_age", history_min_age, 0.0, 5.0);
  r.read("history_max_age", history_max_age, 0.0, 5.0);
  r.read("history_chunk", history_chunk, 0.001, 5.0);
  r.read("motion_distance", motion_distance, 0.001, 5.0);
  r.read("motion_distance_per_m", motion_distance_per_m, 0.0, 1.0);
  r.read("motion_ratio", motion_ratio, 0.01, 1.0);
  r.read("free_space_bin_deg", free_space_bin_deg, 0.1, 10.0);
  r.read("free_space_margin", free_space_margin, 0.0, 10.0);
  r.read("track_support_distance", track_support_distance, 0.0, 10.0);
  r.read("vanish_max_gap", vanish_max_gap, 0.0, 5.0);
  r.read("free_memory", free_memory, 0.0, 30.0);
  r.read("free_memory_heights", free_memory_heights, 2, 0.0, 3.0);
  r.read("free_memory_cell", free_memory_cell, 0.02, 2.0);
  r.read("free_memory_range", free_memory_range, 0.0, 50.0);
  r.read("split_max_size", split_max_size, 0.0, 50.0);
  r.read("history_static_only", history_static_only);
  r.read("view_center_shift", view_center_shift, 0.0, 2.0);
  r.read("occlusion_anchor", occlusion_anchor, 0.0, 2.0);
  r.read("occlusion_margin", occlusion_margin, 0.0, 10.0);
  r.read("static_persistence", static_persistence, 0.0, 10.0);
  r.read("static_cell", static_cell, 0.02, 2.0);
  r.read("static_max_gap", static_max_gap, 0.01, 10.0);
  r.read("static_hold_max", static_hold_max, 0.0, 60.0);
  if (max_cluster_points < min_cluster_points)
    r.fail("max_cluster_points", "must be >= min_cluster_points");
  if (history_max_age - history_min_age < history_chunk)
    r.fail("history_max_age", "the motion-test window must be at least one history_chunk long");
  if (history_max_age <= history_min_age) r.fail("history_max_age", "must be greater than history_min_age");
  if (free_memory_heights.size() == 2 && !(free_memory_heights[1] > free_memory_heights[0]))
    r.fail("free_memory_heights", "the second height must be greater than the first");
}

void AssociationParams::read(ConfigReader& r) {
  r.read("cost_gate", cost_gate, 0.0, 100.0);
  r.read("max_distance", max_distance, 0.01, 20.0);
  r.read("distance_growth", distance_growth, 0.0, 20.0);
  r.read("max_distance_cap", max_distance_cap, 0.01, 50.0);
  r.read("direction_min_speed", direction_min_speed, 1e-3, 20.0);
  r.read("fapp_gate", fapp_gate, 0.01, 20.0);
  r.read("gate_sigma", gate_sigma, 0.0, 100.0);
  r.read("centroid_std", centroid_std, 1e-3, 10.0);
  r.read("distance_weight", distance_weight, 0.0, 100.0);
  r.read("cross_gate", cross_gate, 0.0, 10.0);
  r.read("cross_gate_growth", cross_gate_growth, 0.0, 10.0);
  r.read("cross_gate_after", cross_gate_after, 0.0, 10.0);
  r.read("cross_gate_until", cross_gate_until, 0.0, 100.0);
  r.read("cascade_after", cascade_after, 0.0, 100.0);
  r.read("size_floor", size_floor, 0.0, 10.0);
  r.read("split_shared", split_shared);
  r.read("cross_rank_weight", cross_rank_weight, 1.0, 100.0);
}

void ReassociationParams::read(ConfigReader& r) {
  r.read("enabled", enabled);
  r.read("max_history_points", max_history_points, 1, 100000);
  r.read("max_shift", max_shift, 0.01, 10.0);
  r.read("max_consecutive", max_consecutive, 1, 100000);
}

void TrackParams::read(ConfigReader& r) {
  r.read("confirm_hits", confirm_hits, 1, 1000);
  r.read("confirm_min_speed", confirm_min_speed, 0.0, 50.0);
  r.read("confirm_max_speed", confirm_max_speed, 0.01, 100.0);
  r.read("confirm_min_distance", confirm_min_distance, 0.0, 100.0);
  r.read("confirm_moving_hits", confirm_moving_hits, 0, 1000);
  r.read("max_stationary", max_stationary, 0.01, 1000.0);
  r.read("structure_share", structure_share, 0.01, 1.0);
  r.read("structure_margin", structure_margin, 0.0, 60.0);
  r.read("structure_arrival_distance", structure_arrival_distance, 0.01, 10.0);
  r.read("structure_frames", structure_frames, 0, 1000);
  r.read("structure_decline", structure_decline);
  r.read("new_track_separation", new_track_separation, 0.0, 10.0);
  r.read("reid_speed", reid_speed, 0.0, 50.0);
  r.read("reid_margin", reid_margin, 0.0, 20.0);
  r.read("reid_window", reid_window, 0.0, 60.0);
  r.read("reid_cross_speed", reid_cross_speed, 0.0, 20.0);
  r.read("reid_confirm", reid_confirm);
  r.read("reid_velocity", reid_velocity);
  r.read("merge_margin", merge_margin, 0.0, 10.0);
  r.read("tentative_max_age", tentative_max_age, 0.01, 100.0);
  r.read("tentative_max_misses", tentative_max_misses, 1, 1000);
  r.read("max_coast", max_coast, 0.001, 100.0);
  r.read("coast_velocity_decay", coast_velocity_decay, 0.0, 100.0);
  r.read("free_bin_deg", free_bin_deg, 0.5, 20.0);
  r.read("free_margin", free_margin, 0.0, 10.0);
  r.read("free_frames", free_frames, 1, 1000);
  r.read("velocity_baseline", velocity_baseline, 0.001, 10.0);
  r.read("registration_velocity", registration_velocity);
  r.read("size_smoothing", size_smoothing, 0.01, 1.0);
}

void PerceptionParams::read(ConfigReader& r) {
  auto pp = r.section("paper");
  paper.read(pp);
  r.read("association", association, {"ucon", "fapp"});
  r.read("pose_max_gap", pose_max_gap, 1e-3, 10.0);
  r.read("frame_timeout", frame_timeout, 1e-3, 60.0);
  auto pre = r.section("preprocess");
  preprocess.read(pre);
  auto seg = r.section("segmentation");
  segmentation.read(seg);
  auto as = r.section("object_association");
  object_association.read(as);
  auto re = r.section("reassociation");
  reassociation.read(re);
  auto tr = r.section("tracks");
  tracks.read(tr);
  auto kf = r.section("kalman");
  kalman.read(kf);
}

}  // namespace perception
}  // namespace ucon
