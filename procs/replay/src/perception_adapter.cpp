// perception in lock step: ROBOT_POSE -> onPose, LIDAR_POINTS -> onPoints, then tick(now)
// after every message, as ucon-perception's loop does (the runtime calls tick once per
// handled message). PERCEPTION_STATUS carries wall-clock stage timings and is not replayed.
#include <vector>

#include "adapters.hpp"
#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/perception/perception_node.hpp"

namespace ucon {
namespace replay {

namespace {

class PerceptionAdapter : public NodeAdapter {
 public:
  explicit PerceptionAdapter(const perception::PerceptionParams& p) : node_(p) {}

  std::string name() const override { return "perception"; }
  std::vector<std::string> inputChannels() const override {
    return {channels::kRobotPose, channels::kLidarPoints};
  }
  std::vector<std::string> outputChannels() const override {
    return {channels::kPerceptionObjects, channels::kPerceptionStatic};
  }

  FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                  std::vector<OutputMessage>* out) override {
    if (channel == channels::kRobotPose) {
      robot_pose_t m;
      if (!decodeExact(data, size, &m)) return decodeError();
      ++poses_;
      node_.onPose(m);
    } else if (channel == channels::kLidarPoints) {
      point_cloud_t m;
      if (!decodeExact(data, size, &m)) return decodeError();
      ++frames_;
      emit(node_.onPoints(m), out);
      frame_ms_total_ += node_.lastFrameMs();
    } else {
      return FeedResult::kIgnored;
    }
    emit(node_.tick(node_.now()), out);
    return FeedResult::kHandled;
  }

  std::vector<std::pair<std::string, int64_t>> counters() const override {
    return {{"poses_in", poses_},
            {"frames_in", frames_},
            {"objects_out", objects_out_},
            {"static_out", static_out_},
            {"decode_errors", decode_errors_},
            {"frame_us_mean", frames_ ? static_cast<int64_t>(1e3 * frame_ms_total_ / static_cast<double>(frames_)) : 0}};
  }

 private:
  FeedResult decodeError() {
    ++decode_errors_;
    return FeedResult::kDecodeError;
  }
  void emit(const perception::PerceptionOutput& o, std::vector<OutputMessage>* out) {
    // Same order as ucon-perception's publish(): objects, then static points.
    if (o.objects) {
      out->push_back(encodeOutput(channels::kPerceptionObjects, *o.objects));
      ++objects_out_;
    }
    if (o.static_points) {
      out->push_back(encodeOutput(channels::kPerceptionStatic, *o.static_points));
      ++static_out_;
    }
  }

  perception::PerceptionNode node_;
  int64_t poses_ = 0, frames_ = 0, objects_out_ = 0, static_out_ = 0, decode_errors_ = 0;
  double frame_ms_total_ = 0.0;
};

}  // namespace

std::unique_ptr<NodeAdapter> makePerceptionAdapter(const std::string& yaml, const std::string& source,
                                                   std::string* error) {
  std::vector<ConfigError> errors;
  auto p = loadParams<perception::PerceptionParams>(yaml, source, &errors);
  if (!p) {
    if (error) *error = configErrorText(source, errors);
    return nullptr;
  }
  return std::make_unique<PerceptionAdapter>(*p);
}

}  // namespace replay
}  // namespace ucon
