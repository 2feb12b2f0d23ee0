#pragma once
/// @file faults.hpp
/// `ucon-bench-nav --faults SPEC`: the faults a run injects on its in-process bus
/// (ucon::replay::BusFaults), as a comma list of key=value:
///   drop=P          each delivery of a message to a consumer is lost with probability P (0..1)
///   delay=MS        ... and late by MS milliseconds
///   jitter=MS       ... plus a uniform draw from [0, MS] milliseconds (late messages may overtake)
///   channel=REGEX   only channels whose whole name matches (default: all)
///   kill=NODE@T     NODE (perception, planner, base_controller, odometry) stops at T seconds:
///                   nothing reaches it, nothing it had in flight goes out
///   restart=S       the node killed just before is restarted S seconds later with an empty state
/// e.g. "drop=0.05,jitter=20" or "kill=planner@20,restart=2". Decisions are drawn from the
/// world's seed, so a seed gives the same faults on every run.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ucon/replay/sim_recorder.hpp"

namespace ucon::bench::nav {

struct FaultSpec {
  std::string text;  ///< as given
  double drop = 0.0;
  double delay_ms = 0.0, jitter_ms = 0.0;
  std::string channels;  ///< regex; empty = all
  struct Kill {
    std::string node;
    double at_s = 0.0;
    double restart_s = -1.0;  ///< < 0: never restarted
  };
  std::vector<Kill> kills;
  bool any() const { return drop > 0.0 || delay_ms > 0.0 || jitter_ms > 0.0 || !kills.empty(); }
};

/// Parses SPEC; false and `error` (what is wrong, naming the key) on bad input.
bool parseFaults(const std::string& spec, FaultSpec* out, std::string* error);

/// The bus faults of one run: `seed` draws the decisions; `node_index` maps a node name to its
/// index in the run's node list (-1: not in this run). False and `error` for a kill of a node
/// that is not in the run.
bool toBusFaults(const FaultSpec& spec, uint64_t seed, const std::function<int(const std::string&)>& node_index,
                 replay::BusFaults* out, std::string* error);

}  // namespace ucon::bench::nav
