#include "ucon/foxglove/message_time.hpp"

#include <cstring>

#include "ucon/foxglove/lcm_json.hpp"

namespace ucon {
namespace foxglove {

std::optional<int64_t> MessageClock::ownTime(const LcmTypeInfo& type, const void* data, std::size_t size) {
  if (!type.has_message_time) return std::nullopt;
  const int64_t t = encodedUtime(data, size);
  if (t <= 0) return std::nullopt;
  return t;
}

bool MessageClock::isTimeBase(const LcmTypeInfo& type) {
  for (const char* name : {"ucon.point_cloud_t", "ucon.imu_t", "ucon.robot_pose_t", "ucon.sim_ground_truth_t"}) {
    if (std::strcmp(type.name, name) == 0) return true;
  }
  return false;
}

std::optional<int64_t> MessageClock::timeOf(const LcmTypeInfo& type, const void* data, std::size_t size) {
  const auto own = ownTime(type, data, size);
  if (own && isTimeBase(type)) {
    // The time base sets the clock, even when it jumps (a new run in the same log).
    now_ = *own;
    started_ = true;
    return own;
  }
  if (!started_) return std::nullopt;
  now_ = resolve(own, now_);
  return now_;
}

}  // namespace foxglove
}  // namespace ucon
