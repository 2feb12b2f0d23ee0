#pragma once
/// @file clear_mot.hpp
/// CLEAR-MOT multi-object tracking metrics (Bernardin & Stiefelhagen 2008), computed the way
/// py-motmetrics and TrackEval do (see docs/reference.md §6):
///  - per frame, an object keeps the hypothesis it was matched to at its previous occurrence
///    if that pair is still allowed (within the distance threshold);
///  - the remaining objects and hypotheses are matched by minimum-cost assignment;
///  - an identity switch is counted when an object is matched to a hypothesis other than the
///    one it was last matched to at any earlier time (also after a gap); a switch is a match;
///  - unmatched objects are misses (FN), unmatched hypotheses false positives (FP);
///  - MOTA = 1 - (FN + FP + IDSW) / number of objects over the whole sequence (may be < 0),
///    MOTP = mean distance of the matches.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ucon/mot/hungarian.hpp"

namespace ucon {
namespace mot {

/// A point in the x-y plane [m] with an identity.
struct PointXY {
  int64_t id = 0;
  double x = 0.0;  ///< [m]
  double y = 0.0;  ///< [m]
};

/// An axis-aligned image box with an identity (MOTChallenge: x, y = top-left corner).
struct Box {
  int64_t id = 0;
  double x = 0.0;  ///< left [px]
  double y = 0.0;  ///< top [px]
  double w = 0.0;  ///< width [px], >= 0
  double h = 0.0;  ///< height [px], >= 0
};

/// Intersection over union of two boxes, in [0, 1]; 0 when either is empty.
double boxIou(const Box& a, const Box& b);

/// Distance matrix objects x hypotheses: Euclidean x-y distance [m]; pairs farther than
/// `threshold` [m] (or with non-finite coordinates) are forbidden (inf).
CostMatrix xyDistances(const std::vector<PointXY>& objects, const std::vector<PointXY>& hypotheses,
                       double threshold);

/// Distance matrix objects x hypotheses: 1 - IoU; pairs with IoU < `min_iou` are forbidden.
CostMatrix iouDistances(const std::vector<Box>& objects, const std::vector<Box>& hypotheses,
                        double min_iou);

/// Totals and ratios over a sequence. Rates are per ground-truth object occurrence.
struct ClearMotSummary {
  int64_t num_frames = 0;        ///< frames given to update()
  int64_t num_objects = 0;       ///< ground-truth object occurrences (sum over frames)
  int64_t num_predictions = 0;   ///< hypothesis occurrences (sum over frames)
  int64_t num_matches = 0;       ///< matched pairs, switches included
  int64_t num_switches = 0;      ///< identity switches (IDSW)
  int64_t num_misses = 0;        ///< FN
  int64_t num_false_positives = 0;  ///< FP
  int64_t num_fragmentations = 0;   ///< tracked -> untracked -> tracked again, per object
  int64_t num_unique_objects = 0;   ///< distinct ground-truth ids
  int64_t num_ignored = 0;       ///< ignored object occurrences (e.g. not visible to the sensor)
  int64_t mostly_tracked = 0;    ///< objects matched in >= 80 % of their frames
  int64_t partially_tracked = 0; ///< the rest
  int64_t mostly_lost = 0;       ///< objects matched in < 20 % of their frames
  double total_distance = 0.0;   ///< sum of the matches' distances

  double mota = 0.0;           ///< 1 - (FN + FP + IDSW) / num_objects; NaN if no objects
  double motp = 0.0;           ///< mean match distance (metres, or 1 - IoU); NaN if no match
  double fn_rate = 0.0;        ///< FN / num_objects; NaN if no objects
  double fp_rate = 0.0;        ///< FP / num_objects; NaN if no objects
  double mismatch_rate = 0.0;  ///< IDSW / num_objects; NaN if no objects
  double recall = 0.0;         ///< matches / num_objects; NaN if no objects
  double precision = 0.0;      ///< matches / num_predictions; NaN if no predictions
};

/// What happened to one pair or id in one frame (for inspection and tests).
struct FrameEvents {
  std::vector<std::pair<int64_t, int64_t>> matches;   ///< (object id, hypothesis id)
  std::vector<std::pair<int64_t, int64_t>> switches;  ///< subset of matches that are switches
  std::vector<int64_t> misses;                        ///< object ids
  std::vector<int64_t> false_positives;               ///< hypothesis ids
  std::vector<std::pair<int64_t, int64_t>> ignored;   ///< (ignored object, hypothesis it absorbed or 0)
};

/// Accumulates CLEAR-MOT events frame by frame.
class ClearMotAccumulator {
 public:
  /// Adds one frame. `dist` is objects x hypotheses (rows follow `object_ids`, columns
  /// `hypothesis_ids`); non-finite entries are forbidden pairs. Ids must be unique within a
  /// frame; a repeated id is treated as a separate occurrence of the same id.
  /// Returns the frame's events.
  ///
  /// `ignored` (optional, one flag per object) marks objects that must not be scored, such
  /// as objects the sensor cannot see in this frame (KITTI "don't care" / TrackEval
  /// distractors): they take part in the matching, then an ignored object and the hypothesis
  /// matched to it are dropped — no match, miss, false positive or switch, and the object's
  /// match history is left as it was.
  FrameEvents update(const std::vector<int64_t>& object_ids,
                     const std::vector<int64_t>& hypothesis_ids, const CostMatrix& dist,
                     const std::vector<char>* ignored = nullptr);

  /// Convenience: x-y points with a distance threshold [m].
  FrameEvents updateXY(const std::vector<PointXY>& objects, const std::vector<PointXY>& hypotheses,
                       double threshold, const std::vector<char>* ignored = nullptr);
  /// Convenience: boxes with an IoU threshold.
  FrameEvents updateBoxes(const std::vector<Box>& objects, const std::vector<Box>& hypotheses,
                          double min_iou);

  /// Totals and ratios so far.
  ClearMotSummary summary() const;

 private:
  struct ObjectHistory {
    int64_t last_hypothesis = 0;   ///< hypothesis matched most recently (any earlier frame)
    bool has_match = false;        ///< ever matched
    bool matched_at_last_occurrence = false;
    int64_t frames_present = 0;
    int64_t frames_matched = 0;
    bool tracked_before = false;   ///< was matched in some earlier frame
    bool in_gap = false;           ///< missed since the last match
    int64_t fragmentations = 0;
  };
  std::map<int64_t, ObjectHistory> objects_;
  ClearMotSummary totals_;
};

}  // namespace mot
}  // namespace ucon
