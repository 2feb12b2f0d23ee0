// base_controller in lock step: LockstepReplay (procs/base_controller) already runs the node
// on the control-period grid in message time; this adapter only encodes its outputs.
#include <vector>

#include "adapters.hpp"
#include "ucon/base_controller/replay.hpp"
#include "ucon/channels.hpp"
#include "ucon/config.hpp"

namespace ucon {
namespace replay {

namespace {

class BaseControllerAdapter : public NodeAdapter {
 public:
  explicit BaseControllerAdapter(const base_controller::BaseControllerParams& p) : replay_(p) {}

  std::string name() const override { return "base_controller"; }
  std::vector<std::string> inputChannels() const override {
    return {channels::kRobotPose, channels::kPlannerTrajectory, channels::kBaseEstop};
  }
  std::vector<std::string> outputChannels() const override {
    return {channels::kBaseWheelCmd, channels::kBaseStatus};
  }

  FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                  std::vector<OutputMessage>* out) override {
    const int64_t errors_before = replay_.decodeErrors();
    const int64_t ignored_before = replay_.ignored();
    for (const auto& o : replay_.feed(channel, data, static_cast<int>(size))) {
      if (o.wheel_cmd) out->push_back(encodeOutput(channels::kBaseWheelCmd, *o.wheel_cmd));
      if (o.status) out->push_back(encodeOutput(channels::kBaseStatus, *o.status));
    }
    if (replay_.decodeErrors() != errors_before) return FeedResult::kDecodeError;
    if (replay_.ignored() != ignored_before) return FeedResult::kIgnored;
    return FeedResult::kHandled;
  }

  std::vector<std::pair<std::string, int64_t>> counters() const override {
    auto c = replay_.node().counters();
    c.emplace_back("decode_errors", replay_.decodeErrors());
    return c;
  }

 private:
  base_controller::LockstepReplay replay_;
};

}  // namespace

std::unique_ptr<NodeAdapter> makeBaseControllerAdapter(const std::string& yaml, const std::string& source,
                                                       std::string* error) {
  std::vector<ConfigError> errors;
  auto p = loadParams<base_controller::BaseControllerParams>(yaml, source, &errors);
  if (!p) {
    if (error) *error = configErrorText(source, errors);
    return nullptr;
  }
  if (const std::string bad = p->validate(); !bad.empty()) {
    if (error) *error = source + ": " + bad;
    return nullptr;
  }
  return std::make_unique<BaseControllerAdapter>(*p);
}

}  // namespace replay
}  // namespace ucon
