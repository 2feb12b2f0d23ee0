#pragma once
/// @file params.hpp
/// Parameters of the perception node. deploy/config/perception.yaml maps onto them 1:1 and
/// its values equal the in-class defaults (tests/perception/test_params.cpp): first the
/// paper's parameters, then the engineering ones, stage by stage.

#include <string>
#include <vector>

#include "ucon/kalman/constant_velocity_kalman.hpp"

namespace ucon {
class ConfigReader;

namespace perception {

/// The paper's hyper-parameters (Sec. III; their values are those of Sec. V-A).
struct PaperParams {
  std::vector<double> mu{0.3, 0.3, 0.4};  ///< eq. 1: weights mu1..mu3 of the overlap, direction and size terms, each >= 0
  double d0 = 0.6;      ///< eq. 2 / appendix: a history point matches a current point closer than this [m], > 0
  double gamma = 0.35;  ///< appendix: recovered when more than gamma N_c history points match, (0, 1)
  void read(ConfigReader& r);
};

/// Stage 1: world frame, crop, voxel down-sampling.
struct PreprocessParams {
  double min_range = 0.5;    ///< horizontal distance from the robot centre below which points are the robot's own body [m], >= 0
  double max_range = 15.0;   ///< horizontal crop range [m], > min_range
  double min_height = 0.15;  ///< height above the floor under the robot (world z minus the base's z) below which a point is ground [m]
  double max_height = 2.2;   ///< ... above which it is ceiling [m], > min_height
  int accumulate_frames = 2;  ///< frames merged before down-sampling (a 50 Hz Mid-360 frame is sparse), [1, 10]
  double voxel_size = 0.08;  ///< voxel edge for down-sampling [m], > 0 (0.005..1)
  std::vector<double> sensor_origin{0.0, 0.0, 0.5};  ///< sensor origin in the base frame [m] (for free-space clearing)
  void read(ConfigReader& r);
};

/// Stage 2: clustering and the FAPP-style motion test.
struct SegmentationParams {
  double cluster_tolerance = 0.35;  ///< Euclidean clustering distance [m], > 0
  int min_cluster_points = 4;       ///< smaller clusters are noise (static output), >= 1
  int max_cluster_points = 4000;    ///< larger clusters are static structure, >= min
  double far_cluster_range = 9.0;   ///< points no cluster took this far from the sensor (x-y) [m] ...
  double far_cluster_tolerance = 0.5;  ///< ... are clustered again with this distance (a sparse far scan) [m]; <= cluster_tolerance = off
  double max_object_size = 1.6;     ///< a cluster whose x-y box side exceeds this is static [m]
  double min_object_height = 0.3;   ///< a cluster lower than this (z extent) is not an object [m]
  double history_min_age = 0.5;     ///< reference frames are at least this old [s], >= 0
  double history_max_age = 1.0;     ///< ... and at most this old [s], > history_min_age
  double history_chunk = 0.1;       ///< history frames are merged and indexed in chunks this long [s], > 0
  double motion_distance = 0.1;     ///< a point farther than this from every reference point moved [m]
  double motion_distance_per_m = 0.01;  ///< ... plus this much per metre of range (scan sparsity grows with range) [m/m], >= 0
  double motion_ratio = 0.3;        ///< share of moved points that makes a cluster moving, (0, 1]
  double free_space_bin_deg = 1.0;  ///< angular bin of the free-space check [deg], (0.1, 10]
  double free_space_margin = 0.3;   ///< a moved point also needs the reference to have seen this far past it along its ray, and nothing this much nearer in its bin [m]
  double track_support_distance = 0.8;  ///< a cluster this close to a live track's prediction is dynamic [m]
  double vanish_max_gap = 0.5;      ///< a new point at most this far behind a reference surface that has since gone moved (an object moving away) [m]; 0 = off
  double free_memory = 3.0;         ///< a point the reference could not judge moved when its cell and the eight around it were seen through low (free_memory_heights) within this [s]; 0 = off
  std::vector<double> free_memory_heights{0.2, 0.6};  ///< the band above the floor a ray must cross a cell in [m], 0 <= lo < hi
  double free_memory_cell = 0.2;    ///< x-y cell of that memory [m], > 0
  double free_memory_range = 8.0;   ///< rays are followed this far from the sensor (x-y) [m]
  bool history_static_only = true;  ///< the motion test's reference history leaves out points the frame gave to tracks (someone walking in a tracked person's footsteps, or a mover retracing its path, is not matched against that trail)
  double split_max_size = 4.0;      ///< a cluster too large for an object but at most this large [m] gives its moved points as objects of their own (a mover brushing a pillar); 0 = off
  double view_center_shift = 0.3;   ///< an object seen from one side has its centre moved away from the sensor by up to this (footprint.hpp) [m]; 0 = off
  double occlusion_anchor = 0.1;    ///< a tracked object's view this much narrower across the line of sight than the track and cut on one side by an occluder is centred from its visible edge [m]; 0 = off
  double occlusion_margin = 0.8;    ///< an occluder: a return just beyond the view's edge at least this much nearer than the edge [m]
  double static_persistence = 0.5;  ///< a point reaches PERCEPTION_STATIC once its x-y cell has been occupied this long [s]; 0 = off
  double static_cell = 0.2;         ///< x-y cell of the persistence test [m], > 0
  double static_max_gap = 1.0;      ///< a cell not hit for longer than this starts its occupancy over [s], > 0
  double static_hold_max = 3.0;     ///< a cell hidden behind a return free_space_margin nearer keeps its occupancy through a gap of up to this since its last hit (a crowd walking in front of a box), unless a track took that hit [s]; 0 = off
  void read(ConfigReader& r);
};

/// Stage 3: the gates and ranking around eq. 1 (PaperParams::mu), and the FAPP baseline.
struct AssociationParams {
  double cost_gate = 1.3;            ///< pairs with f(c,h) above this are forbidden
  double max_distance = 1.0;         ///< pairs whose centres are farther apart are forbidden [m]
  double distance_growth = 1.0;      ///< ... plus this per second the track has not been seen [m/s]
  double max_distance_cap = 2.5;     ///< upper bound of the grown distance gate [m]
  double direction_min_speed = 0.3;  ///< below this speed the direction term fades out [m/s], > 0
  double fapp_gate = 0.8;            ///< FAPP baseline: greedy nearest-centroid gate [m]
  double gate_sigma = 3.5;           ///< Mahalanobis gate on the predicted centre (Kalman covariance + centroid_std); 0 = off
  double distance_weight = 1.0;      ///< cost per metre of centre distance added to eq. 1 for ranking (not gated)
  double centroid_std = 0.15;        ///< [m] spread of a cluster centre around the body centre (partial views, merges)
  double cross_gate = 0.4;           ///< a track unseen for cross_gate_after takes no centre farther than this across its last heading [m]; 0 = off
  double cross_gate_growth = 0.15;    ///< ... plus this per second unseen [m/s]
  double cross_gate_after = 0.1;     ///< unseen this long before the cross gate applies [s]
  double cross_gate_until = 2.0;     ///< ... and no longer than this (a longer hiding may hide a turn) [s]
  double cross_rank_weight = 3.0;    ///< rankingDistance(): weight of the offset across a coasting track's heading (1 = plain distance)
  double size_floor = 0.5;           ///< eq. 1's size term divides by max(|s_h|, this) [m]
  double cascade_after = 0.1;        ///< tracks seen within this are matched before the others [s]; 0 = one matching
  bool split_shared = true;          ///< a matched cluster holding the prediction of another track seen within cascade_after that took no cluster is split between them (both velocities settled), each point to the nearer prediction
  void read(ConfigReader& r);
};

/// Stage 4: point-level historical re-association (Sec. III-B, appendix algorithm; d0 and
/// gamma in PaperParams).
struct ReassociationParams {
  bool enabled = true;       ///< off = object-level association only (ablation)
  int max_history_points = 64;  ///< history points kept per track (evenly thinned), >= 1
  double max_shift = 0.4;    ///< recovered points must be centred this close to the prediction [m] (not the occluder in front)
  int max_consecutive = 75;  ///< frames in a row a track may live on re-association alone, >= 1
  void read(ConfigReader& r);
};

/// Stage 5: track management.
struct TrackParams {
  int confirm_hits = 4;             ///< measurements needed to confirm a tentative track, >= 1
  double confirm_min_speed = 0.15;  ///< and its filtered speed must reach this [m/s], >= 0
  double confirm_max_speed = 2.5;   ///< ... but not exceed this (a jumping cluster is not a person) [m/s]
  double confirm_min_distance = 0.3;  ///< and it must have moved this far from where it was first seen [m], >= 0
  int confirm_moving_hits = 3;      ///< and this many of its clusters must have passed the motion test, >= 0
  double max_stationary = 3.0;      ///< a track whose clusters fail the motion test, or that stays slower than confirm_min_speed, this long is deleted [s]
  double structure_share = 0.8;     ///< a confirmed track's measurement with at least this share of its points on x-y cells occupied since before the track was created or came to its place lies on structure, (0, 1]
  double structure_margin = 1.0;    ///< ... occupied since this long before the track was created or arrived at its place [s], >= 0
  double structure_arrival_distance = 0.5;  ///< [m] its place: its measured centre has stayed within this distance of it since it came there, > 0
  int structure_frames = 5;         ///< a confirmed track measured on structure this many frames in a row is deleted; 0 = off
  bool structure_decline = true;    ///< a coasting track does not take a measurement on structure that did not move (counted as a frame on structure)
  double new_track_separation = 0.7;  ///< no new track from a cluster this close to an existing track [m]
  double reid_speed = 1.8;          ///< a track confirmed within reid_speed * t + reid_margin of where a coasting track was last seen t ago takes over its identity [m/s]; 0 = off
  double reid_margin = 0.5;         ///< [m]
  double reid_window = 8.0;         ///< deleted confirmed tracks stay candidates for re-identification this long [s]
  bool reid_velocity = true;        ///< a new track where a coasting or recently deleted track's object would be now, had it kept its velocity, starts with that velocity instead of at rest (an object back from behind a pillar walks on)
  bool reid_confirm = true;         ///< a tentative track within the gate of a coasting or recently deleted track (a returning object) is confirmed on confirm_hits and confirm_moving_hits alone, without the speed and distance tests
  double reid_cross_speed = 0.1;    ///< candidates are ranked with reid_speed along and this across their last heading [m/s]; 0 = by plain distance
  double merge_margin = 0.3;        ///< a matched cluster larger than the track's box by this is a merge [m]
  double tentative_max_age = 1.0;   ///< a tentative track older than this is deleted [s]
  int tentative_max_misses = 2;     ///< consecutive misses that delete a tentative track, >= 1
  double max_coast = 1.5;           ///< a track unseen for this long is deleted [s], > 0
  double coast_velocity_decay = 1.0;  ///< while unseen, the velocity decays with this time constant [s] (people stop and turn); 0 = off
  double free_bin_deg = 3.0;        ///< angular bins of the "seen through" check of unseen tracks [deg], [0.5, 20]
  double free_margin = 0.5;         ///< a track is seen through when the nearest return in its bin is this far behind it [m]
  int free_frames = 3;              ///< an unseen track seen through this many frames in a row is deleted, >= 1
  double velocity_baseline = 0.2;   ///< velocity measurement differences positions this far apart [s], > 0
  bool registration_velocity = true;  ///< the x-y displacement over that baseline aligns the two views' points (registration.hpp) instead of differencing their centres
  double size_smoothing = 0.3;      ///< weight of a new box size in the track's size, (0, 1]
  void read(ConfigReader& r);
};

/// The track filter's noise (common/kalman, Sec. IV-A) as perception ships it: a cluster centre
/// is noisier than the filter library's generic default (partial views, merges).
inline kalman::KalmanParams trackFilterDefaults() {
  kalman::KalmanParams k;
  k.accel_psd_xy = 0.5;
  k.accel_psd_z = 0.05;
  k.position_std = 0.08;
  k.velocity_std = 0.4;
  k.initial_velocity_std = 1.0;
  return k;
}

/// All of the node.
struct PerceptionParams {
  PaperParams paper;
  std::string association = "ucon";  ///< "ucon" (eq. 1 + Hungarian + re-association) or "fapp"
  double pose_max_gap = 0.1;          ///< a frame farther than this from any pose has a stale pose; a point past the newest pose is extrapolated at most this far [s], > 0
  double frame_timeout = 0.2;         ///< no frame for this long (message time) -> outputs invalid [s]
  PreprocessParams preprocess;
  SegmentationParams segmentation;
  AssociationParams object_association;
  ReassociationParams reassociation;
  TrackParams tracks;
  kalman::KalmanParams kalman = trackFilterDefaults();
  void read(ConfigReader& r);
  bool useUcon() const { return association == "ucon"; }
};

}  // namespace perception
}  // namespace ucon
