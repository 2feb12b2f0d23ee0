#pragma once
/// @file message_time.hpp
/// The time policy shared by ucon-mcap and ucon-foxglove-bridge: a message's time is its own
/// utime (sensor or simulation time), never the time it was received.
///
/// The message clock follows the stack's time base, the messages every node takes its time
/// from: LiDAR points and IMU samples (sensor time), robot poses and the simulator's ground
/// truth. Any other message keeps its own utime when that lies within kWindowUs of the clock;
/// otherwise it takes the clock's time. That covers utime <= 0 ("invalid" in every ucon type),
/// the types whose utime is the wall clock by definition (LOG_METADATA, PROC_STATUS), and
/// processes that stamp their status with the wall clock while the stack runs on simulation
/// or sensor time (the logger): they land where they happened in the run instead of decades
/// away. Before the first time-base message there is no clock: the caller holds such
/// messages and resolves them against the first time-base time, or uses their own time.

#include <cstddef>
#include <cstdint>
#include <optional>

namespace ucon {
namespace foxglove {

struct LcmTypeInfo;

class MessageClock {
 public:
  /// A message's own utime counts only this close to the clock [us] (10 minutes).
  static constexpr int64_t kWindowUs = 600'000'000;

  /// The message's own time [us]: its utime when its type has message time and utime > 0;
  /// nullopt otherwise.
  static std::optional<int64_t> ownTime(const LcmTypeInfo& type, const void* data, std::size_t size);

  /// True for the types that set the clock (point_cloud_t, imu_t, robot_pose_t,
  /// sim_ground_truth_t).
  static bool isTimeBase(const LcmTypeInfo& type);

  /// Time [us] for this message under the policy above (advancing the clock); nullopt while
  /// there is no clock and the message is not of the time base.
  std::optional<int64_t> timeOf(const LcmTypeInfo& type, const void* data, std::size_t size);

  /// The time [us] a message whose own time is `own` gets at clock `clock`: its own time
  /// within kWindowUs of the clock, the clock otherwise.
  static int64_t resolve(std::optional<int64_t> own, int64_t clock) {
    return own && *own >= clock - kWindowUs && *own <= clock + kWindowUs ? *own : clock;
  }

  /// The clock [us]: the latest time-base time, or a later message's own time within the
  /// window; 0 before the first time-base message.
  int64_t now() const { return now_; }
  bool started() const { return started_; }

 private:
  int64_t now_ = 0;
  bool started_ = false;
};

}  // namespace foxglove
}  // namespace ucon
