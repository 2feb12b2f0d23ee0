#pragma once
/// @file track_manager.hpp
/// Stage 5 of the pipeline: the tracks and their lifecycle. A track starts tentative from a
/// moving cluster, is confirmed once it has moved like an object (hits, speed, distance,
/// clusters that passed the motion test), coasts while unseen, and is deleted when it coasts
/// too long, when the sensor sees through where it should be (negative evidence), when it
/// stays static, or when a newer track takes over its identity (re-identification). Each track
/// carries a constant-velocity Kalman filter (common/kalman, Sec. IV-A) updated with the
/// measured position and a velocity measured over a baseline of a few frames.

#include <cstdint>
#include <deque>
#include <vector>

#include <Eigen/Core>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/perception/angular_grid.hpp"
#include "ucon/perception/association.hpp"
#include "ucon/perception/measurement.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/preprocess.hpp"
#include "ucon/status_report.hpp"

namespace ucon {
namespace perception {

/// One tracked object.
struct Track {
  int64_t id = 0;
  int8_t state = 0;             ///< tracked_object_t::STATE_*
  int8_t last_association = 0;  ///< tracked_object_t::ASSOC_*
  kalman::ConstantVelocityKalman kf;
  int64_t created_utime = 0;
  int64_t last_seen_utime = 0;  ///< last measurement
  Eigen::Vector2d seen_velocity = Eigen::Vector2d::Zero();  ///< filtered x-y velocity right after it [m/s]
  int hits = 0;
  int misses = 0;               ///< consecutive frames without a measurement
  int age_frames = 0;
  int consecutive_reassoc = 0;
  bool confirmed_once = false;  ///< was confirmed at some point
  bool reidentified = false;    ///< handed its identity to a new track
  int free_count = 0;           ///< consecutive frames an unseen track was seen through
  int moving_hits = 0;          ///< measurements from clusters that passed the motion test
  int64_t last_moving_utime = 0;  ///< last such measurement
  int64_t last_fast_utime = 0;    ///< last frame its filtered speed reached confirm_min_speed
  int structure_frames = 0;       ///< consecutive measurements lying on structure older than the track
  Eigen::Vector2d arrival_xy = Eigen::Vector2d::Zero();  ///< where it was when it last moved structure_arrival_distance [m]
  int64_t arrival_utime = 0;      ///< ... and when: since then it has stayed at its place [us]
  int num_points = 0;           ///< points of the latest measurement
  Eigen::Vector2d size = Eigen::Vector2d::Zero();  ///< smoothed x-y box size [m]
  double size_z = 0.0;          ///< smoothed z extent [m]
  double width = 0.0;           ///< extent across the line of sight in views not cut by an occluder [m]; 0 = none yet
  Eigen::Vector2d first_center = Eigen::Vector2d::Zero();  ///< where it was first measured [m]
  Points history;               ///< T_c: the latest measurement's points (thinned)
  struct Measured {
    int64_t utime = 0;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    Points points;  ///< thinned; empty unless tracks.registration_velocity
  };
  std::deque<Measured> measured;  ///< the measurements of the last velocity baseline
  explicit Track(const kalman::KalmanParams& p) : kf(p) {}
};

/// Whether a track's filtered x-y velocity is settled: its variance (the trace of the x-y
/// velocity block) at most that of one velocity measurement in each axis, 2 velocity_std^2.
/// A new track starts at kalman.initial_velocity_std and gets there after a few measurements.
bool velocitySettled(const Track& t, double velocity_std);

class TrackManager {
 public:
  /// `coarse`: the bins of the "seen through" check (tracks.free_bin_deg), over which
  /// frame.nearest_coarse is kept.
  TrackManager(const PerceptionParams& params, const AngularGrid& coarse);

  /// Tracks in creation order.
  const std::vector<Track>& tracks() const { return tracks_; }

  /// Advances every filter to `utime` [us], the time of the frame being processed.
  void predict(int64_t utime, StatusReport& status);
  /// The tracks' predicted x-y centres [m].
  std::vector<Eigen::Vector2d> predictedCenters() const;
  /// The tracks as object-level association sees them at `utime`.
  std::vector<TrackView> views(int64_t utime) const;

  /// Updates track `j` with measurement `m` at `utime`; `how` is tracked_object_t::ASSOC_*,
  /// `moving` whether the measured points passed the motion test.
  /// `on_structure`: the measurement lies on x-y cells occupied since before the track existed.
  void update(std::size_t j, const Measurement& m, int64_t utime, int8_t how, bool moving, bool on_structure,
              StatusReport& status);

  /// The lifecycle step of the tracks that existed before this frame (`updated`: per track,
  /// whether it was measured): confirmation, re-identification, coasting, negative evidence
  /// from `frame`, deletion. Deleted tracks leave tracks().
  void manage(int64_t utime, const std::vector<char>& updated, const Frame& frame, StatusReport& status);

  /// Whether a track's predicted centre lies within new_track_separation of `center`: a
  /// cluster there is a fragment of a tracked object, not a new one.
  bool nearTrack(const Eigen::Vector2d& center) const;

  /// Track j (coasting) was offered a measurement on structure whose points did not move and
  /// did not take it: it stays unseen, and the frame counts toward tracks.structure_frames.
  void declineOnStructure(std::size_t j) { ++tracks_[j].structure_frames; }
  /// Starts a tentative track from a moving cluster's measurement. False (and counted as a
  /// kalman error) when its filter cannot start.
  bool start(const Measurement& m, int64_t utime, StatusReport& status);

 private:
  /// A confirmed track deleted recently, kept for re-identification.
  struct Lost {
    int64_t id = 0;
    int age_frames = 0;
    Eigen::Vector2d last_center = Eigen::Vector2d::Zero();
    Eigen::Vector2d seen_velocity = Eigen::Vector2d::Zero();
    int64_t last_seen_utime = 0;
  };
  /// A deleted (or coasting) track as re-identification remembers it.
  static Lost lostRecord(const Track& t);
  /// The coasting track (`*coasting`) or recently deleted one (`*lost`) whose object `fresh`
  /// is, by the re-identification gate and score; both null when none (or reid_speed is 0).
  void reidCandidate(const Track& fresh, Track** coasting, const Lost** lost);
  /// tracks.reid_velocity: the velocity a new track `fresh` starts with, that of the object
  /// reidCandidate() finds when `fresh` lies where it would be had it kept that velocity;
  /// zero otherwise.
  Eigen::Vector3d returningVelocity(const Track& fresh);
  /// `fresh`, just confirmed, takes over the identity of reidCandidate()'s answer for it.
  void reidentify(Track& fresh, Track* coasting, const Lost* lost, StatusReport& status);
  bool seenThrough(const Track& t, const Frame& frame) const;

  TrackParams params_;
  kalman::KalmanParams kalman_;
  int max_history_points_;
  AngularGrid coarse_;
  std::vector<Track> tracks_;  ///< ordered by creation
  std::deque<Lost> lost_;
  int64_t next_id_ = 1;
  int64_t last_utime_ = 0;  ///< time all filters refer to
  double last_dt_ = 0.0;    ///< time since the previous processed frame [s]
};

}  // namespace perception
}  // namespace ucon
