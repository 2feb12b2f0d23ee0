#include "ucon/mot/mot_log.hpp"

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cstdio>
#include <sys/stat.h>
#include <vector>

#include "ucon/channels.hpp"

namespace ucon {
namespace mot {
namespace {

constexpr uint8_t kSync[4] = {0xED, 0xA1, 0xDA, 0x01};
constexpr long kEventHeaderBytes = 4 + 8 + 8 + 4 + 4;

template <class Msg>
bool decode(const lcm::LogEvent* ev, Msg* out) {
  const int n = out->decode(ev->data, 0, ev->datalen);
  return n >= 0 && n == ev->datalen;
}

}  // namespace

std::optional<ClearMotSummary> evaluateLog(const std::string& path, const LogEvalOptions& opt,
                                           LogMatchStats* stats_out, std::string* error) {
  LogMatchStats stats;
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    if (stats_out) *stats_out = stats;
    return std::nullopt;
  };

  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return fail("cannot open '" + path + "'");
  {
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return fail("cannot open '" + path + "'");
    uint8_t head[4] = {0, 0, 0, 0};
    const size_t n = std::fread(head, 1, 4, f);
    std::fclose(f);
    if (n < 4 || !std::equal(head, head + 4, kSync))
      return fail("'" + path + "' is not an LCM log (no sync word 0xEDA1DA01 at its start)");
  }

  lcm::LogFile log(path, "r");
  if (!log.good()) return fail("cannot open '" + path + "' as an LCM log");

  std::vector<sim_ground_truth_t> gts;
  std::vector<tracked_objects_t> frames;
  long pos = 0;
  for (;;) {
    const lcm::LogEvent* ev = log.readNextEvent();
    const long after = std::ftell(log.getFilePtr());
    if (!ev) {
      // Bytes after the last complete event that do not form an event: a truncated tail.
      if (pos < static_cast<long>(st.st_size)) {
        stats.truncated = true;
        stats.warning = "log is truncated or corrupt after byte " + std::to_string(pos) + " of " +
                        std::to_string(static_cast<long long>(st.st_size)) + " (" +
                        std::to_string(stats.events) + " events read)";
      }
      break;
    }
    const long expected = kEventHeaderBytes + static_cast<long>(ev->channel.size()) + ev->datalen;
    if (after - pos != expected && !stats.truncated) {
      // lcm::LogFile skipped bytes looking for the next sync word: corrupt data.
      stats.truncated = true;
      stats.warning = "corrupt data in the log between bytes " + std::to_string(pos) + " and " +
                      std::to_string(after - expected);
    }
    pos = after;
    ++stats.events;
    if (ev->channel == channels::kSimGroundTruth) {
      sim_ground_truth_t gt;
      if (decode(ev, &gt)) {
        gts.push_back(std::move(gt));
        ++stats.ground_truth_messages;
      } else {
        ++stats.undecodable_messages;
      }
    } else if (ev->channel == channels::kPerceptionObjects) {
      tracked_objects_t t;
      if (decode(ev, &t)) {
        frames.push_back(std::move(t));
        ++stats.perception_messages;
      } else {
        ++stats.undecodable_messages;
      }
    }
  }
  if (stats.truncated && !opt.allow_truncated)
    return fail("'" + path + "': " + stats.warning + "; use --allow-truncated to evaluate the rest");
  if (gts.empty()) return fail("'" + path + "' holds no decodable SIM_GROUND_TRUTH message");
  if (frames.empty()) return fail("'" + path + "' holds no decodable PERCEPTION_OBJECTS message");

  // Log order is receive order; evaluate in message time.
  std::stable_sort(gts.begin(), gts.end(),
                   [](const sim_ground_truth_t& a, const sim_ground_truth_t& b) { return a.utime < b.utime; });
  std::stable_sort(frames.begin(), frames.end(),
                   [](const tracked_objects_t& a, const tracked_objects_t& b) { return a.utime < b.utime; });

  ClearMotAccumulator acc;
  const int64_t max_gap_us = static_cast<int64_t>(opt.max_time_gap_s * 1e6);
  for (const auto& f : frames) {
    if (f.utime <= 0) {
      ++stats.invalid_frames;
      continue;  // no time: cannot be paired with ground truth
    }
    auto it = std::lower_bound(gts.begin(), gts.end(), f.utime,
                               [](const sim_ground_truth_t& g, int64_t t) { return g.utime < t; });
    const sim_ground_truth_t* best = nullptr;
    int64_t best_gap = 0;
    for (auto cand : {it, it == gts.begin() ? gts.end() : it - 1}) {
      if (cand == gts.end()) continue;
      const int64_t gap = std::llabs(cand->utime - f.utime);
      if (!best || gap < best_gap) {
        best = &*cand;
        best_gap = gap;
      }
    }
    if (!best || best_gap > max_gap_us) {
      ++stats.frames_without_ground_truth;
      continue;
    }
    if (!f.valid) ++stats.invalid_frames;
    acc.updateXY(groundTruthAt(*best, f.utime, opt), hypothesesOf(f, opt), opt.threshold_m);
    ++stats.frames_evaluated;
  }
  if (stats_out) *stats_out = stats;
  return acc.summary();
}

}  // namespace mot
}  // namespace ucon
