#include "ucon/mot/mot_log.hpp"

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cstdio>
#include <sys/stat.h>
#include <type_traits>
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

  auto bad = [&](const std::string& what) {
    fail(what);
    return false;
  };
  std::vector<sim_ground_truth_t> gts;
  std::vector<tracked_objects_t> frames;
  // Decodes an event into `out` (counted in *n) or counts it undecodable.
  auto keep = [&](const lcm::LogEvent* ev, auto* out, int64_t* n) {
    typename std::remove_pointer_t<decltype(out)>::value_type msg;
    if (decode(ev, &msg)) {
      out->push_back(std::move(msg));
      ++*n;
    } else {
      ++stats.undecodable_messages;
    }
  };
  // Reads one log, keeping the ground truth and/or the perception frames; false on a file that
  // cannot be read as an LCM log (the reason in *error).
  auto scan = [&](const std::string& file, bool take_gt, bool take_frames) -> bool {
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0) return bad("cannot open '" + file + "'");
    {
      FILE* f = std::fopen(file.c_str(), "rb");
      if (!f) return bad("cannot open '" + file + "'");
      uint8_t head[4] = {0, 0, 0, 0};
      const size_t n = std::fread(head, 1, 4, f);
      std::fclose(f);
      if (n < 4 || !std::equal(head, head + 4, kSync))
        return bad("'" + file + "' is not an LCM log (no sync word 0xEDA1DA01 at its start)");
    }
    lcm::LogFile log(file, "r");
    if (!log.good()) return bad("cannot open '" + file + "' as an LCM log");
    long pos = 0;
    int64_t events = 0;
    for (;;) {
      const lcm::LogEvent* ev = log.readNextEvent();
      const long after = std::ftell(log.getFilePtr());
      if (!ev) {
        // Bytes after the last complete event that do not form an event: a truncated tail.
        if (pos < static_cast<long>(st.st_size) && !stats.truncated) {
          stats.truncated = true;
          stats.warning = "'" + file + "' is truncated or corrupt after byte " + std::to_string(pos) + " of " +
                          std::to_string(static_cast<long long>(st.st_size)) + " (" + std::to_string(events) +
                          " events read)";
        }
        break;
      }
      const long expected = kEventHeaderBytes + static_cast<long>(ev->channel.size()) + ev->datalen;
      if (after - pos != expected && !stats.truncated) {
        // lcm::LogFile skipped bytes looking for the next sync word: corrupt data.
        stats.truncated = true;
        stats.warning = "corrupt data in '" + file + "' between bytes " + std::to_string(pos) + " and " +
                        std::to_string(after - expected);
      }
      pos = after;
      ++events;
      ++stats.events;
      if (take_gt && ev->channel == channels::kSimGroundTruth) {
        keep(ev, &gts, &stats.ground_truth_messages);
      } else if (take_frames && ev->channel == channels::kPerceptionObjects) {
        keep(ev, &frames, &stats.perception_messages);
      }
    }
    return true;
  };
  const bool separate = !opt.objects_log.empty();
  if (!scan(path, true, !separate)) return std::nullopt;
  if (separate && !scan(opt.objects_log, false, true)) return std::nullopt;
  const std::string& objects_file = separate ? opt.objects_log : path;
  if (stats.truncated && !opt.allow_truncated)
    return fail(stats.warning + "; use --allow-truncated to evaluate the rest");
  if (gts.empty()) return fail("'" + path + "' holds no decodable SIM_GROUND_TRUTH message");
  if (frames.empty()) return fail("'" + objects_file + "' holds no decodable PERCEPTION_OBJECTS message");

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
