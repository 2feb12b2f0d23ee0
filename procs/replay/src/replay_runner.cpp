#include "ucon/replay/replay_runner.hpp"

#include <cstdio>

#include "ucon/channels.hpp"
#include "ucon/log_metadata_t.hpp"
#include "ucon/runtime/log_reader.hpp"

namespace ucon {
namespace replay {

ReplayResult replayLog(NodeAdapter& node, const std::string& in_path, const std::string& out_path) {
  ReplayResult r;
  runtime::LogReader reader;
  if (!reader.open(in_path)) {
    r.error = reader.error();
    return r;
  }
  runtime::LogWriterFile writer;
  if (!writer.open(out_path, &r.error)) return r;

  runtime::LogEvent ev;
  std::vector<OutputMessage> outs;
  runtime::LogReadStatus s;
  while ((s = reader.next(&ev)) == runtime::LogReadStatus::kOk) {
    ++r.summary.events;
    outs.clear();
    switch (node.feed(ev.channel, ev.data.data(), ev.data.size(), &outs)) {
      case FeedResult::kHandled: ++r.summary.handled; break;
      case FeedResult::kIgnored: ++r.summary.ignored; break;
      case FeedResult::kDecodeError: ++r.summary.decode_errors; break;
    }
    for (const auto& o : outs) {
      if (!writer.write(o.channel, o.data.data(), o.data.size(), o.utime)) {
        r.error = out_path + ": write failed after " + std::to_string(r.summary.outputs) + " messages";
        writer.close();
        std::remove(out_path.c_str());
        return r;
      }
      ++r.summary.outputs;
      ++r.summary.outputs_per_channel[o.channel];
    }
  }
  writer.close();
  if (s != runtime::LogReadStatus::kEnd) {
    r.error = reader.error() + " (after " + std::to_string(r.summary.events) + " good events)";
    std::remove(out_path.c_str());
    return r;
  }
  r.ok = true;
  return r;
}

std::optional<std::string> configFromLog(const std::string& log_path, const std::string& node,
                                         std::string* error) {
  runtime::LogReader reader;
  if (!reader.open(log_path)) {
    if (error) *error = reader.error();
    return std::nullopt;
  }
  runtime::LogEvent ev;
  runtime::LogReadStatus s;
  const std::string key = "config/" + node + ".yaml";
  while ((s = reader.next(&ev)) == runtime::LogReadStatus::kOk) {
    if (ev.channel != channels::kLogMetadata) continue;
    log_metadata_t m;
    if (!decodeExact(ev.data.data(), ev.data.size(), &m)) {
      if (error) *error = log_path + ": undecodable LOG_METADATA at byte offset " + std::to_string(ev.offset);
      return std::nullopt;
    }
    for (std::size_t i = 0; i < m.keys.size() && i < m.values.size(); ++i) {
      if (m.keys[i] == key) return m.values[i];
    }
    if (error) *error = log_path + ": its LOG_METADATA has no " + key;
    return std::nullopt;
  }
  if (error) {
    *error = s == runtime::LogReadStatus::kEnd ? log_path + ": no LOG_METADATA event (not recorded by ucon-logger?)"
                                               : reader.error();
  }
  return std::nullopt;
}

std::string exactChannelRegex(const std::vector<std::string>& channels) {
  std::string re = "^(";
  for (std::size_t i = 0; i < channels.size(); ++i) re += (i ? "|" : "") + channels[i];
  return re + ")$";
}

}  // namespace replay
}  // namespace ucon
