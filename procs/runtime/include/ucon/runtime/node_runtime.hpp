#pragma once
/// @file node_runtime.hpp
/// The I/O side shared by every process's main.cpp: opening LCM with a clear error,
/// SIGINT/SIGTERM handling, typed subscriptions that count undecodable messages, the one loop
/// shape (handleTimeout + tick), and periodic status publishing. Node classes never see this.

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ucon/process_status_t.hpp"
#include "ucon/status_report.hpp"

namespace ucon {
namespace runtime {

/// Installs SIGINT/SIGTERM handlers that set the exit flag (idempotent).
void installSignalHandlers();
/// True once SIGINT/SIGTERM arrived or requestExit() was called.
bool exitRequested();
/// Sets the exit flag (tests, fatal errors).
void requestExit();
/// Clears the exit flag (tests that run several loops in one process).
void resetExitFlag();

/// Wall clock [us] — for latency and status timestamps only, never for node logic.
int64_t wallUtime();

/// Prints "[name] level: message" to stderr with the wall-clock time.
void logLine(const std::string& name, const char* level, const std::string& message);

/// LCM connection, subscriptions and the loop of one process.
class NodeRuntime {
 public:
  /// Opens LCM at `url` (empty = LCM_DEFAULT_URL or the runtime default). Returns nullptr and
  /// fills `error` if the URL is malformed or the provider cannot start.
  static std::unique_ptr<NodeRuntime> open(const std::string& process_name, const std::string& url,
                                           std::string* error);

  NodeRuntime(const NodeRuntime&) = delete;
  NodeRuntime& operator=(const NodeRuntime&) = delete;
  ~NodeRuntime();

  lcm::LCM& lcm() { return *lcm_; }
  const std::string& url() const { return url_; }
  StatusReport& status() { return status_; }

  /// Subscribes `handler` to `channel` (a regex). Messages that fail to decode are counted as
  /// "decode_errors" on the status and dropped. The subscription queues up to `queue_capacity`
  /// messages while the loop is busy (LCM's default of 30 drops bursts silently).
  template <class Msg>
  void subscribe(const std::string& channel,
                 std::function<void(const Msg&, const std::string& channel)> handler,
                 int queue_capacity = kDefaultQueueCapacity);

  /// Subscription queue length used unless a subscriber asks otherwise.
  static constexpr int kDefaultQueueCapacity = 1000;

  /// Publishes `msg` on `channel`; counts "publish_errors" on failure.
  template <class Msg>
  void publish(const std::string& channel, const Msg& msg) {
    if (lcm_->publish(channel, &msg) != 0) status_.count("publish_errors");
  }

  /// Status channel and period; the status message is built from status() with utime from
  /// `message_time` (the node's message clock). Period in wall time (status is for humans).
  void setStatusChannel(const std::string& channel, double period_s,
                        std::function<int64_t()> message_time);

  /// The loop: `while (!exitRequested()) { handleTimeout(timeout_ms); tick(); status }`.
  /// `tick` may be empty. Returns 0 on a clean exit, 1 if LCM failed while running.
  int spin(int timeout_ms, const std::function<void()>& tick);

  /// Handles at most one message (or times out); for tests and custom loops. Returns
  /// handleTimeout's result.
  int handleOnce(int timeout_ms);

  /// Publishes the status message now.
  void publishStatus();

 private:
  NodeRuntime(std::string name, std::string url, std::unique_ptr<lcm::LCM> lcm);

  struct HandlerBase {
    virtual ~HandlerBase() = default;
  };
  template <class Msg>
  struct Handler : HandlerBase {
    NodeRuntime* owner;
    std::function<void(const Msg&, const std::string&)> fn;
    void onRaw(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
      Msg msg;
      const int n = msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size));
      if (n < 0 || static_cast<uint32_t>(n) != rbuf->data_size) {
        owner->status_.count("decode_errors");
        return;
      }
      fn(msg, channel);
    }
  };

  std::string name_;
  std::string url_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::vector<std::unique_ptr<HandlerBase>> handlers_;
  StatusReport status_;
  std::string status_channel_;
  double status_period_s_ = 1.0;
  std::function<int64_t()> message_time_;
  std::chrono::steady_clock::time_point next_status_;
};

template <class Msg>
void NodeRuntime::subscribe(const std::string& channel,
                            std::function<void(const Msg&, const std::string&)> handler,
                            int queue_capacity) {
  auto h = std::make_unique<Handler<Msg>>();
  h->owner = this;
  h->fn = std::move(handler);
  lcm::Subscription* sub = lcm_->subscribe(channel, &Handler<Msg>::onRaw, h.get());
  if (sub) sub->setQueueCapacity(queue_capacity);
  handlers_.push_back(std::move(h));
}

}  // namespace runtime
}  // namespace ucon
