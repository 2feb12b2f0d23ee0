#include "ucon/base_controller/motor_backend.hpp"

#include <lcm/lcm-cpp.hpp>

#include "ucon/base_controller/serial_frame.hpp"

namespace ucon {
namespace base_controller {

bool LcmMotorBackend::send(const ucon::wheel_cmd_t& cmd) {
  if (lcm_.publish(channel_, &cmd) != 0) {
    ++errors_;
    return false;
  }
  ++sent_;
  return true;
}

std::vector<std::pair<std::string, int64_t>> LcmMotorBackend::counters() const {
  return {{"motor_cmds_sent", sent_}, {"motor_send_errors", errors_}};
}

bool SerialMotorBackend::send(const ucon::wheel_cmd_t& cmd) {
  const mecanum::WheelSpeeds w{cmd.w_fl, cmd.w_fr, cmd.w_rl, cmd.w_rr};
  int clamped = 0;
  const auto frame = encodeWheelFrame(seq_++, cmd.enable, kin_.toMotor(w), &clamped);
  clamped_ += clamped;
  if (!port_->write(frame.data(), frame.size())) return false;
  ++sent_;
  return true;
}

std::vector<std::pair<std::string, int64_t>> SerialMotorBackend::counters() const {
  return {{"motor_cmds_sent", sent_},
          {"motor_frames_dropped", port_->droppedWrites()},
          {"motor_send_errors", port_->writeErrors()},
          {"motor_speeds_clamped", clamped_}};
}

}  // namespace base_controller
}  // namespace ucon
