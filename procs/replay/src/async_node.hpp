#pragma once
// The recorder's pipelined node (sim_recorder.cpp, RecorderConfig::async_delay_us): a node on a
// worker thread of its own whose outputs fall due a fixed delay after their inputs.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "ucon/cpu_time.hpp"
#include "ucon/replay/node_adapter.hpp"

namespace ucon {
namespace replay {

// A node on a worker thread of its own (RecorderConfig::async_delay_us). The loop's thread
// queues inputs with their bus time; the worker feeds them in order and keeps every output
// with its due time (input's bus time + delay). Before a step the loop takes the outputs due
// by then, after waiting until the worker has handled every input that could produce one.
class AsyncNode {
 public:
  struct Due {
    int64_t due = 0;
    OutputMessage msg;
  };

  AsyncNode(NodeAdapter* node, int64_t delay_us) : node_(node), delay_us_(delay_us) {
    worker_ = std::thread([this] { run(); });
  }
  ~AsyncNode() { stop(); }

  // Ends the worker and returns its thread's CPU seconds. Inputs still queued are handled
  // first (their outputs are not delivered): how many the worker had got through when the run
  // ended depends on timing, and the node's counters, read after the run, must not.
  double stop() {
    if (worker_.joinable()) {
      {
        std::lock_guard<std::mutex> lk(m_);
        quit_ = true;
      }
      cv_.notify_all();
      worker_.join();
    }
    return cpu_s_;
  }
  AsyncNode(const AsyncNode&) = delete;
  AsyncNode& operator=(const AsyncNode&) = delete;

  void push(int64_t bus_time, const std::string& channel, const std::vector<uint8_t>& data) {
    {
      std::lock_guard<std::mutex> lk(m_);
      in_.push_back({bus_time, channel, data});
    }
    times_.push_back(bus_time);
    cv_.notify_all();
  }

  // Appends to `out` the outputs due at or before `t`, in production order. `on_wait`
  // (optional) is called with true before and false after waiting for the worker.
  void takeDue(int64_t t, std::vector<Due>* out, const std::function<void(bool)>& on_wait) {
    // Inputs whose outputs are due by t: queued at bus time <= t - delay.
    while (!times_.empty() && times_.front() + delay_us_ <= t) {
      times_.pop_front();
      ++needed_;
    }
    std::unique_lock<std::mutex> lk(m_);
    const auto done = [&] { return handled_ >= needed_ || failed_; };
    if (!done()) {
      if (on_wait) on_wait(true);
      cv_.wait(lk, done);
      if (on_wait) on_wait(false);
    }
    if (failed_) throw std::runtime_error("async node " + node_->name() + ": " + error_);
    while (!out_.empty() && out_.front().due <= t) {
      out->push_back(std::move(out_.front()));
      out_.pop_front();
    }
  }

 private:
  struct Input {
    int64_t bus_time;
    std::string channel;
    std::vector<uint8_t> data;
  };

  void run() {
    const double cpu0 = ucon::threadCpuSeconds();
    std::vector<OutputMessage> outs;
    for (;;) {
      Input in;
      {
        std::unique_lock<std::mutex> lk(m_);
        cv_.wait(lk, [&] { return quit_ || !in_.empty(); });
        if (in_.empty()) break;  // quit, every input pushed handled
        in = std::move(in_.front());
        in_.pop_front();
      }
      outs.clear();
      bool failed = false;
      std::string err;
      try {
        node_->feed(in.channel, in.data.data(), in.data.size(), &outs);
      } catch (const std::exception& e) {
        failed = true, err = e.what();
      } catch (...) {
        failed = true, err = "unknown exception";
      }
      {
        std::lock_guard<std::mutex> lk(m_);
        for (auto& o : outs) out_.push_back({in.bus_time + delay_us_, std::move(o)});
        ++handled_;
        if (failed) failed_ = true, error_ = err;
      }
      cv_.notify_all();
      if (failed) break;
    }
    cpu_s_ = ucon::threadCpuSeconds() - cpu0;  // read by stop() after the join
  }

  NodeAdapter* node_;
  int64_t delay_us_;
  std::deque<int64_t> times_;  // loop thread only: bus times of inputs not yet required
  int64_t needed_ = 0;         // loop thread only: inputs that must be handled before the next take
  std::mutex m_;
  std::condition_variable cv_;
  std::deque<Input> in_;
  std::deque<Due> out_;
  int64_t handled_ = 0;
  bool quit_ = false, failed_ = false;
  std::string error_;
  double cpu_s_ = 0.0;
  std::thread worker_;
};

}  // namespace replay
}  // namespace ucon
