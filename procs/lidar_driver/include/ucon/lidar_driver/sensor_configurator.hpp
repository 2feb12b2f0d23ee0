#pragma once
/// @file sensor_configurator.hpp
/// The control path for every listed sensor, as a state machine without sockets: it says which
/// control frames to send, from which host socket and when, and consumes the answers. The
/// process moves the bytes and supplies a monotonic time; tests drive it directly.
///
/// Per sensor: [discovery, broadcast every retry_interval_s until the sensor answers] ->
/// configuration steps, each its own set command, each resent until acknowledged:
///   first where data goes: state-info (0x0005), point (0x0006) and IMU (0x0007) host IP/ports
///   in one command (as Livox's SDK does), then, once that is acknowledged, together:
///   point data type (0x0000), scan pattern (0x0001, non-repetitive), install attitude zero
///   (0x0012), IMU on or off (0x001C), work mode (0x001A: 0x01 sampling or 0x02 idle)
/// -> done. (livox_ros_driver2 sets the same keys at every start, each by its own command: a
/// sensor left on another data type or pattern by another tool is put back.) The steps after
/// the first do not wait for each other, so one the sensor ignores does not hold the rest.
/// Without end unless control.timeout_s > 0. A rejected step (ret_code != 0) is retried too,
/// unless it is optional (pattern, attitude, the info query of --check): an optional step is
/// skipped with a warning when rejected or unanswered after 3 requests.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/livox/control.hpp"

namespace ucon {
namespace lidar_driver {

/// A datagram to send, and the host socket to send it from.
struct OutgoingDatagram {
  enum class Via { kDiscovery, kCommand };
  Via via = Via::kCommand;  ///< kDiscovery: from host_ip:discovery_port; kCommand: host command port
  std::array<uint8_t, 4> ip{};
  uint16_t port = 0;
  std::vector<uint8_t> bytes;
};

/// What the configurator knows about one listed sensor.
struct SensorControlState {
  enum class Phase { kDiscovering, kConfiguring, kDone };
  Phase phase = Phase::kDiscovering;
  bool ip_known = false;              ///< false while an "auto" sensor has not answered
  std::array<uint8_t, 4> ip{};        ///< its address (configured or the discovery answer's source)
  uint16_t command_port = 0;          ///< from the discovery answer (or the configured default)
  std::string serial;                 ///< from the discovery answer
  std::string firmware;               ///< "a.b.c.d" from the info query (--check), else empty
  int time_sync_type = -1;            ///< key 0x800C from the info query or a push; -1 unknown
  int step = 0;                       ///< 0: the host configuration; 1: the others, together;
                                      ///< stepCount(): done
  std::vector<bool> step_done;        ///< per step: acknowledged (or skipped, if optional)
  int attempts = 0;                   ///< discovery requests / requests of the first open step
  int configured_count = 0;           ///< times configuration completed (1 + reconfigurations)
  std::string last_rejection;         ///< the latest refusal, e.g. "ret_code 1 for key 0x001A"
};

class SensorConfigurator {
 public:
  /// `params` must be valid (DriverParams::read checks them). With `query_info` a last,
  /// optional step asks each sensor for its serial and firmware (ucon-lidar-driver --check).
  explicit SensorConfigurator(const DriverParams& params, bool query_info = false);

  /// Requests due at monotonic time `t_s` [s] (the first call starts the clock). Also fails
  /// the whole path when control.timeout_s > 0 has passed with a sensor not configured.
  std::vector<OutgoingDatagram> poll(double t_s);

  /// A datagram received on the discovery socket (0.0.0.0:discovery_port), from `src`.
  /// Requests (ours, looped back by the broadcast) and foreign frames are ignored.
  void onDiscoveryDatagram(const std::array<uint8_t, 4>& src, const uint8_t* data,
                           std::size_t size, double t_s);
  /// A datagram received on the host command port, from `src`.
  void onCommandDatagram(const std::array<uint8_t, 4>& src, const uint8_t* data, std::size_t size,
                         double t_s);
  /// A push message (0x0102) on the host push port: notes the sensor's time-sync type.
  void onPushDatagram(const std::array<uint8_t, 4>& src, const uint8_t* data, std::size_t size);

  /// Sensor `i` went silent (rebooted?): find and configure it again.
  void restart(std::size_t i, double t_s);

  bool allDone() const;
  bool failed() const { return failed_; }
  /// Why it failed (empty unless failed()): what was asked, of whom, and what to check.
  const std::string& failure() const { return failure_; }
  /// What the driver waits for, per sensor not done; empty when all are done.
  std::string waitingFor() const;
  /// Warnings since the last call (a step skipped, a rejection, an unlisted sensor answering).
  std::vector<std::string> takeWarnings();

  std::size_t size() const { return sensors_.size(); }
  const SensorControlState& sensor(std::size_t i) const { return sensors_[i]; }
  /// Index of the listed sensor with this address, or -1.
  int indexOf(const std::array<uint8_t, 4>& ip) const;
  int requestsSent() const { return requests_sent_; }
  int ignoredDatagrams() const { return ignored_; }

  /// Name of configuration step `step` (e.g. "point data type"), for messages.
  const char* stepName(int step) const;
  int stepCount() const { return static_cast<int>(steps_.size()); }

 private:
  struct Step {
    const char* name;
    bool optional;
    int max_attempts;  // 0 = unlimited
  };
  livox::ControlFrame request(std::size_t i, int step);
  void finishStep(std::size_t i, int step, double t_s);
  void beginConfiguring(std::size_t i, double t_s);
  /// Steps open now for sensor i (0 alone, then every unfinished one).
  std::vector<int> openSteps(std::size_t i) const;
  void fail(double t_s);
  std::string describe(std::size_t i) const;

  DriverParams params_;
  std::vector<Step> steps_;
  std::vector<SensorControlState> sensors_;
  struct StepState {
    std::vector<uint32_t> seqs;  // every request sent for it (a late ack counts)
    int attempts = 0;
    double next_send_s = 0.0;
    std::string rejection;  // the sensor's last refusal, e.g. "ret_code 1 for key 0x001A"
  };
  std::vector<std::vector<StepState>> step_state_;  // per sensor, per step
  std::array<uint8_t, 4> host_ip_{};
  uint32_t seq_ = 1;
  double start_s_ = -1;
  double next_discovery_s_ = 0;
  int discovery_requests_ = 0;
  int requests_sent_ = 0;
  int ignored_ = 0;
  bool failed_ = false;
  std::string failure_;
  std::vector<std::string> warnings_;
  std::vector<std::array<uint8_t, 4>> unlisted_seen_;
};

const char* toString(SensorControlState::Phase p);

}  // namespace lidar_driver
}  // namespace ucon
