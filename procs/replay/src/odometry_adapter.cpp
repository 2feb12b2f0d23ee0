// odometry in lock step: LIDAR_IMU -> onImu (ROBOT_POSE, or the configured pose_channel), then processFrames (ODOMETRY_STATUS of
// the frames that sample lets run); LIDAR_POINTS -> onPoints (ODOMETRY_STATUS of frames dropped
// or run at once), as ucon-odometry's handlers publish them. ODOMETRY_HEALTH carries wall-clock
// timings and is not replayed.
#include <vector>

#include "adapters.hpp"
#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/odometry/odometry_node.hpp"

namespace ucon {
namespace replay {

namespace {

class OdometryAdapter : public NodeAdapter {
 public:
  explicit OdometryAdapter(const odometry::OdometryParams& p) : node_(p), pose_channel_(p.pose_channel) {}

  std::string name() const override { return "odometry"; }
  std::vector<std::string> inputChannels() const override { return {channels::kLidarImu, channels::kLidarPoints}; }
  std::vector<std::string> outputChannels() const override {
    return {pose_channel_, channels::kOdometryStatus};
  }

  FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                  std::vector<OutputMessage>* out) override {
    if (channel == channels::kLidarImu) {
      imu_t m;
      if (!decodeExact(data, size, &m)) return decodeError();
      ++imu_;
      emit(node_.onImu(m), out);
      emit(node_.processFrames(), out);
    } else if (channel == channels::kLidarPoints) {
      point_cloud_t m;
      if (!decodeExact(data, size, &m)) return decodeError();
      ++frames_;
      emit(node_.onPoints(m), out);
    } else {
      return FeedResult::kIgnored;
    }
    return FeedResult::kHandled;
  }

  std::vector<std::pair<std::string, int64_t>> counters() const override {
    const auto& n = node_.estimator().counters();
    return {{"imu_in", imu_},
            {"frames_in", frames_},
            {"poses_out", poses_out_},
            {"statuses_out", statuses_out_},
            {"frames_updated", n.frames_updated},
            {"frames_skipped", n.frames_skipped},
            {"frames_dropped", n.frames_dropped},
            {"imu_gaps", n.imu_gaps},
            {"decode_errors", decode_errors_}};
  }

 private:
  FeedResult decodeError() {
    ++decode_errors_;
    return FeedResult::kDecodeError;
  }
  void emit(const odometry::OdometryOutput& o, std::vector<OutputMessage>* out) {
    if (o.pose) {
      out->push_back(encodeOutput(pose_channel_, *o.pose));
      ++poses_out_;
    }
    for (const auto& s : o.statuses) {
      out->push_back(encodeOutput(channels::kOdometryStatus, s));
      ++statuses_out_;
    }
  }

  odometry::OdometryNode node_;
  std::string pose_channel_;
  int64_t imu_ = 0, frames_ = 0, poses_out_ = 0, statuses_out_ = 0, decode_errors_ = 0;
};

}  // namespace

std::unique_ptr<NodeAdapter> makeOdometryAdapter(const std::string& yaml, const std::string& source,
                                                 std::string* error) {
  std::vector<ConfigError> errors;
  auto p = loadParams<odometry::OdometryParams>(yaml, source, &errors);
  if (!p) {
    if (error) *error = configErrorText(source, errors);
    return nullptr;
  }
  if (const std::string bad = p->validate(); !bad.empty()) {
    if (error) *error = source + ": " + bad;
    return nullptr;
  }
  return std::make_unique<OdometryAdapter>(*p);
}

}  // namespace replay
}  // namespace ucon
