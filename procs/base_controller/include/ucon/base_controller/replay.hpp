#pragma once
/// @file replay.hpp
/// Lock-step replay of recorded messages through a BaseController, ticking on message time
/// (ControlTimer message mode). Pure: the caller reads the log (lcm::LogFile) and hands over
/// each event's channel and bytes. Same log, same outputs, byte for byte.

#include <cstdint>
#include <string>
#include <vector>

#include "ucon/base_controller/control_timer.hpp"
#include "ucon/base_controller/controller.hpp"

namespace ucon {
namespace base_controller {

class LockstepReplay {
 public:
  explicit LockstepReplay(const BaseControllerParams& params);

  /// Handles one recorded event: the ticks due before it, then the message itself
  /// (ROBOT_POSE, PLANNER_TRAJECTORY, BASE_ESTOP; other channels are ignored). Returns every
  /// output produced, in order. Events that do not decode are counted and dropped.
  std::vector<BaseControllerOutput> feed(const std::string& channel, const void* data, int size);

  const BaseController& node() const { return node_; }
  int64_t decodeErrors() const { return decode_errors_; }
  int64_t ignored() const { return ignored_; }

 private:
  BaseController node_;
  ControlTimer timer_;
  int64_t decode_errors_ = 0;
  int64_t ignored_ = 0;
};

}  // namespace base_controller
}  // namespace ucon
