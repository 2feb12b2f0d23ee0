#pragma once
/// @file mcap_export.hpp
/// LCM log events -> MCAP: every ucon channel as JSON with its generated jsonschema (topic =
/// the LCM channel name), plus the Foxglove views of convert.hpp. Log time and publish time
/// of each message = its message time (message_time.hpp); messages before the first
/// time-base message wait for it and are resolved against its time. Events whose type is not a ucon type, or
/// whose bytes do not decode, are counted per channel and left out (LCM's own LCM_SELF_TEST
/// silently). No file I/O: events in, McapWriter calls out.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ucon/foxglove/convert.hpp"
#include "ucon/foxglove/mcap_writer.hpp"
#include "ucon/foxglove/message_time.hpp"

namespace ucon {
namespace foxglove {

struct ExportOptions {
  bool raw_json = true;   ///< the ucon messages themselves, as JSON
  bool foxglove = true;   ///< the Foxglove views (point clouds, transforms, scene updates, map)
  /// Messages held while waiting for the first time-base message; beyond it they are written
  /// at their own utime (0 without one) [-].
  std::size_t max_pending = 10000;
};

struct ExportStats {
  int64_t events = 0;            ///< log events seen
  int64_t messages = 0;          ///< MCAP messages written (raw + Foxglove)
  int64_t untimed = 0;           ///< messages written at another time than their own utime
  std::map<std::string, int64_t> unknown_type;   ///< channel -> events of no ucon type
  std::map<std::string, int64_t> undecodable;    ///< channel -> events that did not decode
};

class McapExporter {
 public:
  /// `writer` must be started; the exporter writes to it and finish() finishes it.
  McapExporter(McapWriter* writer, const ViewParams& view, const ExportOptions& options);

  /// One log event. False once the writer failed (see the writer's error()).
  bool add(const std::string& channel, const void* data, std::size_t size);

  /// Writes what is still pending (the static map, untimed messages of a log without any
  /// timed one) and finishes the MCAP file.
  bool finish();

  const ExportStats& stats() const { return stats_; }
  const ConvertStats& convertStats() const { return converter_.stats(); }

 private:
  struct Pending {
    std::string channel;
    std::vector<uint8_t> data;
  };
  bool process(const std::string& channel, const LcmTypeInfo& type, const void* data, std::size_t size,
               int64_t utime);
  bool writeMessage(uint16_t channel_id, int64_t utime, const std::string& json);
  uint16_t rawChannel(const std::string& channel, const LcmTypeInfo& type);
  uint16_t foxgloveChannel(const FoxgloveTopic& topic);

  McapWriter* writer_;
  ExportOptions options_;
  FoxgloveConverter converter_;
  MessageClock clock_;
  ExportStats stats_;
  std::vector<Pending> pending_;
  std::map<std::string, uint16_t> schema_ids_;         // schema name -> id
  std::map<std::string, uint16_t> raw_channels_;       // LCM channel -> channel id
  std::map<FoxgloveTopic, uint16_t> fox_channels_;     // Foxglove topic -> channel id
  std::map<uint16_t, uint32_t> sequence_;              // channel id -> next sequence number
  std::vector<FoxgloveMessage> converted_;
  std::string json_;
};

}  // namespace foxglove
}  // namespace ucon
