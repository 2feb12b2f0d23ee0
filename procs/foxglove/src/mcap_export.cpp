#include "ucon/foxglove/mcap_export.hpp"

#include "ucon/foxglove/foxglove_schemas.hpp"
#include "ucon/foxglove/json_writer.hpp"
#include "ucon/foxglove/lcm_json.hpp"

namespace ucon {
namespace foxglove {

namespace {
constexpr const char* kLcmSelfTest = "LCM_SELF_TEST";
uint64_t toNs(int64_t utime) { return utime > 0 ? static_cast<uint64_t>(utime) * 1000u : 0u; }
}  // namespace

McapExporter::McapExporter(McapWriter* writer, const ViewParams& view, const ExportOptions& options)
    : writer_(writer), options_(options), converter_(view) {}

uint16_t McapExporter::rawChannel(const std::string& channel, const LcmTypeInfo& type) {
  const auto it = raw_channels_.find(channel);
  if (it != raw_channels_.end()) return it->second;
  uint16_t& schema = schema_ids_[type.name];
  if (schema == 0) schema = writer_->addSchema(type.name, "jsonschema", type.json_schema);
  const uint16_t id = writer_->addChannel(schema, channel, "json", {{"lcm_type", type.name}});
  raw_channels_[channel] = id;
  return id;
}

uint16_t McapExporter::foxgloveChannel(const FoxgloveTopic& topic) {
  const auto it = fox_channels_.find(topic);
  if (it != fox_channels_.end()) return it->second;
  uint16_t& schema = schema_ids_[topic.schema_name];
  if (schema == 0) schema = writer_->addSchema(topic.schema_name, "jsonschema", foxgloveSchema(topic.schema_name));
  const uint16_t id = writer_->addChannel(schema, topic.topic, "json");
  fox_channels_[topic] = id;
  return id;
}

bool McapExporter::writeMessage(uint16_t channel_id, int64_t utime, const std::string& json) {
  if (channel_id == 0xFFFF) return false;
  const uint64_t t = toNs(utime);
  ++stats_.messages;
  return writer_->write(channel_id, sequence_[channel_id]++, t, t, json.data(), json.size());
}

bool McapExporter::process(const std::string& channel, const LcmTypeInfo& type, const void* data,
                           std::size_t size, int64_t utime) {
  if (options_.raw_json) {
    json_.clear();
    JsonWriter w(&json_);
    if (!type.to_json(data, static_cast<int>(size), w)) {
      ++stats_.undecodable[channel];
      return true;
    }
    if (!writeMessage(rawChannel(channel, type), utime, json_)) return false;
  }
  if (options_.foxglove) {
    converted_.clear();
    if (!converter_.convert(channel, type, data, size, utime, &converted_)) {
      if (!options_.raw_json) ++stats_.undecodable[channel];
      return true;
    }
    for (const auto& m : converted_) {
      if (!writeMessage(foxgloveChannel(m.topic), utime, m.json)) return false;
    }
  }
  return writer_->ok();
}

bool McapExporter::add(const std::string& channel, const void* data, std::size_t size) {
  ++stats_.events;
  if (channel == kLcmSelfTest) return writer_->ok();  // LCM's own start-up check, not a ucon message
  const LcmTypeInfo* type = findLcmType(data, size);
  if (!type) {
    ++stats_.unknown_type[channel];
    return writer_->ok();
  }
  const auto own = MessageClock::ownTime(*type, data, size);
  const auto t = clock_.timeOf(*type, data, size);
  if (!t) {
    // No clock yet: wait for the first time-base message (at most max_pending messages).
    if (pending_.size() < options_.max_pending) {
      const auto* b = static_cast<const uint8_t*>(data);
      pending_.push_back(Pending{channel, std::vector<uint8_t>(b, b + size)});
      return writer_->ok();
    }
    if (!own) ++stats_.untimed;
    return process(channel, *type, data, size, own.value_or(0));
  }
  if (!pending_.empty()) {
    // The clock starts: what waited for it takes its time, in log order, before this one.
    std::vector<Pending> waiting;
    waiting.swap(pending_);
    for (const auto& p : waiting) {
      const LcmTypeInfo& pt = *findLcmType(p.data.data(), p.data.size());
      const auto pown = MessageClock::ownTime(pt, p.data.data(), p.data.size());
      const int64_t pt_time = MessageClock::resolve(pown, *t);
      if (!pown || *pown != pt_time) ++stats_.untimed;
      if (!process(p.channel, pt, p.data.data(), p.data.size(), pt_time)) return false;
    }
  }
  if (!own || *own != *t) ++stats_.untimed;
  return process(channel, *type, data, size, *t);
}

bool McapExporter::finish() {
  // A log without any time-base message: what waited keeps its own time (0 without one).
  std::vector<Pending> waiting;
  waiting.swap(pending_);
  for (const auto& p : waiting) {
    const LcmTypeInfo& type = *findLcmType(p.data.data(), p.data.size());
    const auto own = MessageClock::ownTime(type, p.data.data(), p.data.size());
    if (!own) ++stats_.untimed;
    if (!process(p.channel, type, p.data.data(), p.data.size(), own.value_or(0))) return false;
  }
  if (options_.foxglove) {
    converted_.clear();
    converter_.flushMap(clock_.now(), true, &converted_);
    for (const auto& m : converted_) {
      if (!writeMessage(foxgloveChannel(m.topic), clock_.now(), m.json)) return false;
    }
  }
  return writer_->finish();
}

}  // namespace foxglove
}  // namespace ucon
