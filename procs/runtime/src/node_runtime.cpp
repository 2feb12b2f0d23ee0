#include "ucon/runtime/node_runtime.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <malloc.h>
#include <regex>
#include <sys/time.h>

#include "ucon/channels.hpp"

namespace ucon {
namespace runtime {

namespace {
volatile std::sig_atomic_t g_exit = 0;
void onSignal(int) { g_exit = 1; }

// LCM 1.3.1 accepts some malformed URLs silently (and aborts on others); check the shape here
// so the user gets a message naming what is wrong.
bool checkUrl(const std::string& url, std::string* error) {
  static const std::regex kUdpm(R"(udpm://(\d{1,3}\.\d{1,3}\.\d{1,3}\.\d{1,3})(:(\d{1,5}))?(\?.*)?)");
  static const std::regex kOther(R"((memq|file|tcpq)://.*)");
  std::smatch m;
  if (std::regex_match(url, m, kUdpm)) {
    const std::string ip = m[1];
    int first = std::atoi(ip.c_str());
    if (first < 224 || first > 239) {
      *error = "LCM URL '" + url + "': " + ip + " is not a multicast address (224.0.0.0/4)";
      return false;
    }
    if (m[3].matched) {
      int port = std::atoi(std::string(m[3]).c_str());
      if (port <= 0 || port > 65535) {
        *error = "LCM URL '" + url + "': port out of range 1..65535";
        return false;
      }
    }
    return true;
  }
  if (std::regex_match(url, kOther)) return true;
  *error = "LCM URL '" + url +
           "' is not understood; expected e.g. udpm://239.255.76.67:7667?ttl=0 or memq://";
  return false;
}
}  // namespace

void installSignalHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool exitRequested() { return g_exit != 0; }
void requestExit() { g_exit = 1; }
void resetExitFlag() { g_exit = 0; }

int64_t wallUtime() {
  struct timeval tv;
  gettimeofday(&tv, nullptr);
  return static_cast<int64_t>(tv.tv_sec) * 1000000 + tv.tv_usec;
}

void logLine(const std::string& name, const char* level, const std::string& message) {
  const int64_t now = wallUtime();
  std::time_t secs = static_cast<std::time_t>(now / 1000000);
  std::tm tm{};
  localtime_r(&secs, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%H:%M:%S", &tm);
  std::fprintf(stderr, "%s.%03d [%s] %s: %s\n", stamp, static_cast<int>((now / 1000) % 1000),
               name.c_str(), level, message.c_str());
}

std::unique_ptr<NodeRuntime> NodeRuntime::open(const std::string& process_name,
                                               const std::string& url, std::string* error) {
  std::string u = url;
  if (u.empty()) {
    const char* env = std::getenv("LCM_DEFAULT_URL");
    u = (env && *env) ? env : channels::kDefaultLcmUrl;
  }
  std::string err;
  if (!checkUrl(u, &err)) {
    if (error) *error = err;
    return nullptr;
  }
  // LCM's default receive buffer (the kernel default, ~208 KiB) holds ~60 ms of the full-rate
  // stack's traffic: a stall that long loses point clouds. Ask for 4 MiB unless the URL says.
  if (u.rfind("udpm://", 0) == 0 && u.find("recv_buf_size") == std::string::npos) {
    u += (u.find('?') == std::string::npos ? "?" : "&") + std::string("recv_buf_size=4194304");
  }
  auto lcm = std::make_unique<lcm::LCM>(u);
  if (!lcm->good()) {
    if (error) {
      *error = "cannot open LCM at '" + u +
               "' (for udpm: is there a multicast route? try ttl=0, or check the port is free)";
    }
    return nullptr;
  }
  return std::unique_ptr<NodeRuntime>(new NodeRuntime(process_name, u, std::move(lcm)));
}

NodeRuntime::NodeRuntime(std::string name, std::string url, std::unique_ptr<lcm::LCM> lcm)
    : name_(std::move(name)),
      url_(std::move(url)),
      lcm_(std::move(lcm)),
      outbox_(
          [this](const std::string& channel, int64_t, const uint8_t* data, std::size_t size) {
            if (lcm_->publish(channel, data, static_cast<unsigned int>(size)) != 0) count("publish_errors");
          },
          [this](const char* level, const std::string& text) { logLine(name_, level, text); }) {
  next_status_ = std::chrono::steady_clock::now();
}

NodeRuntime::~NodeRuntime() = default;

int64_t NodeRuntime::counter(const std::string& name) const {
  const auto it = counters_.find(name);
  return it == counters_.end() ? 0 : it->second;
}

void NodeRuntime::setStatus(const std::string& channel, double period_s, std::function<StatusReport&()> report,
                            std::function<int64_t()> clock) {
  status_channel_ = channel;
  status_period_s_ = period_s;
  status_report_ = std::move(report);
  status_clock_ = std::move(clock);
  next_status_ = std::chrono::steady_clock::now() +
                 std::chrono::microseconds(static_cast<int64_t>(period_s * 1e6));
}

void NodeRuntime::publishStatus() {
  if (status_channel_.empty() || !status_report_) return;
  StatusReport& r = status_report_();
  for (const char* c : {"decode_errors", "publish_errors"}) r.setCounter(c, counter(c));
  for (const auto& extra : status_extras_) extra(r);
  const int64_t t = status_clock_ ? status_clock_() : 0;
  publish(status_channel_, r.build(t, wallUtime()));
}

void NodeRuntime::subscribeRaw(const std::string& channel, std::function<void(const uint8_t*, std::size_t)> fn,
                               int queue_capacity) {
  auto h = std::make_unique<RawHandler>();
  h->fn = std::move(fn);
  lcm::Subscription* sub = lcm_->subscribe(channel, &RawHandler::onRaw, h.get());
  if (sub) sub->setQueueCapacity(queue_capacity);
  handlers_.push_back(std::move(h));
}

int NodeRuntime::handleOnce(int timeout_ms) { return lcm_->handleTimeout(timeout_ms); }

int NodeRuntime::spin(int timeout_ms, const std::function<void()>& tick) {
  return loop([timeout_ms] { return timeout_ms; }, tick);
}

int NodeRuntime::loop(const std::function<int()>& timeout_ms, const std::function<void()>& tick) {
  while (!exitRequested()) {
    const int rc = lcm_->handleTimeout(timeout_ms());
    if (rc < 0) {
      // A signal interrupts the wait (EINTR): that is the normal way out, not an error.
      if (exitRequested() || errno == EINTR) continue;
      logLine(name_, "error", "LCM stopped working (handleTimeout < 0); exiting");
      return 1;
    }
    if (tick) tick();
    const auto now = std::chrono::steady_clock::now();
    if (!status_channel_.empty() && now >= next_status_) {
      publishStatus();
      next_status_ = now + std::chrono::microseconds(static_cast<int64_t>(status_period_s_ * 1e6));
    }
    if (trim_period_s_ > 0.0 && now >= next_trim_) {
      if (next_trim_ != std::chrono::steady_clock::time_point{}) ::malloc_trim(0);
      next_trim_ = now + std::chrono::microseconds(static_cast<int64_t>(trim_period_s_ * 1e6));
    }
  }
  return 0;
}

}  // namespace runtime
}  // namespace ucon
