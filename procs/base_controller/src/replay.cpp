#include "ucon/base_controller/replay.hpp"

#include "ucon/channels.hpp"

namespace ucon {
namespace base_controller {

namespace {
template <class Msg>
bool decode(const void* data, int size, Msg* out) {
  if (data == nullptr || size < 0) return false;
  return out->decode(data, 0, size) == size;
}
}  // namespace

LockstepReplay::LockstepReplay(const BaseControllerParams& params)
    : node_(params), timer_(ControlTimer::Mode::kMessage, params.control.rate_hz) {}

std::vector<BaseControllerOutput> LockstepReplay::feed(const std::string& channel, const void* data,
                                                       int size) {
  std::vector<BaseControllerOutput> out;
  auto handle = [&](int64_t utime, auto&& call) {
    timer_.observe(utime, 0);
    for (int64_t t : timer_.due(0)) out.push_back(node_.tick(t));
    out.push_back(call());
  };
  if (channel == channels::kRobotPose) {
    ucon::robot_pose_t m;
    if (!decode(data, size, &m)) {
      ++decode_errors_;
      return out;
    }
    handle(m.utime, [&] { return node_.onPose(m); });
  } else if (channel == channels::kPlannerTrajectory) {
    ucon::trajectory_t m;
    if (!decode(data, size, &m)) {
      ++decode_errors_;
      return out;
    }
    handle(m.utime, [&] { return node_.onTrajectory(m); });
  } else if (channel == channels::kBaseEstop) {
    ucon::estop_t m;
    if (!decode(data, size, &m)) {
      ++decode_errors_;
      return out;
    }
    handle(m.utime, [&] { return node_.onEstop(m); });
  } else {
    ++ignored_;
  }
  return out;
}

}  // namespace base_controller
}  // namespace ucon
