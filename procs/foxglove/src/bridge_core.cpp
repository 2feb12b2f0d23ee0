#include "ucon/foxglove/bridge_core.hpp"

#include "ucon/channels.hpp"
#include "ucon/foxglove/foxglove_schemas.hpp"
#include "ucon/foxglove/json_writer.hpp"
#include "ucon/foxglove/lcm_json.hpp"

namespace ucon {
namespace foxglove {

BridgeCore::BridgeCore(const ViewParams& view) : converter_(view) {
  for (const auto& c : channels::all()) {
    if (const LcmTypeInfo* t = findLcmTypeByName(c.type.c_str())) registerChannel(c.name, *t);
  }
}

uint32_t BridgeCore::channelFor(const std::string& topic, const std::string& schema_name, const std::string& schema) {
  const auto key = std::make_pair(topic, schema_name);
  const auto it = by_topic_.find(key);
  if (it != by_topic_.end()) return it->second;
  const uint32_t id = next_id_++;
  WsChannel c;
  c.id = id;
  c.topic = topic;
  c.schema_name = schema_name;
  c.schema = schema;
  channels_[id] = c;
  by_topic_[key] = id;
  new_channels_.push_back(id);
  return id;
}

void BridgeCore::registerChannel(const std::string& channel, const LcmTypeInfo& type) {
  if (lcm_channels_.count(channel)) return;
  std::vector<uint32_t> ids;
  ids.push_back(channelFor(channel, type.name, type.json_schema));
  for (const auto& t : foxgloveTopicsFor(channel, type.name))
    ids.push_back(channelFor(t.topic, t.schema_name, foxgloveSchema(t.schema_name)));
  lcm_channels_[channel] = std::move(ids);
}

std::vector<WsChannel> BridgeCore::takeNewChannels() {
  std::vector<WsChannel> out;
  for (uint32_t id : new_channels_) out.push_back(channels_.at(id));
  new_channels_.clear();
  return out;
}

void BridgeCore::onLcm(const std::string& channel, const void* data, std::size_t size,
                       const std::function<bool(uint32_t)>& wanted, std::vector<BridgeOutput>* out) {
  ++stats_.lcm_messages;
  if (channel == "LCM_SELF_TEST") return;  // LCM's own start-up check, not a ucon message
  const LcmTypeInfo* type = findLcmType(data, size);
  if (!type) {
    ++stats_.unknown_type;
    return;
  }
  registerChannel(channel, *type);
  const auto own = MessageClock::ownTime(*type, data, size);
  const auto t = clock_.timeOf(*type, data, size);
  // Before the first time-base message a message keeps its own utime (0 without one).
  const int64_t utime = t ? *t : own.value_or(0);
  if (!own || *own != utime) ++stats_.untimed;
  const uint64_t ns = static_cast<uint64_t>(utime) * 1000u;
  const auto& ids = lcm_channels_.at(channel);

  if (wanted(ids[0])) {
    auto json = std::make_shared<std::string>();
    JsonWriter w(json.get());
    if (!type->to_json(data, static_cast<int>(size), w)) {
      ++stats_.undecodable;
      return;
    }
    out->push_back(BridgeOutput{ids[0], ns, std::move(json)});
    ++stats_.converted;
  }
  bool any_view = false;
  for (std::size_t i = 1; i < ids.size(); ++i) any_view = any_view || wanted(ids[i]);
  // The static map grows from every static_points_t message, watched or not.
  const bool feeds_map = std::string(type->name) == "ucon.static_points_t";
  if (!any_view && !feeds_map) return;
  converted_.clear();
  if (!converter_.convert(channel, *type, data, size, utime, &converted_)) {
    ++stats_.undecodable;
    return;
  }
  for (auto& m : converted_) {
    const auto it = by_topic_.find(std::make_pair(m.topic.topic, m.topic.schema_name));
    if (it == by_topic_.end() || !wanted(it->second)) continue;
    out->push_back(BridgeOutput{it->second, ns, std::make_shared<const std::string>(std::move(m.json))});
    ++stats_.converted;
  }
}

void BridgeCore::currentMap(std::vector<BridgeOutput>* out) {
  converted_.clear();
  converter_.flushMap(clock_.now(), false, &converted_);
  for (auto& m : converted_) {
    const auto it = by_topic_.find(std::make_pair(m.topic.topic, m.topic.schema_name));
    if (it == by_topic_.end()) continue;
    out->push_back(BridgeOutput{it->second, nowNs(), std::make_shared<const std::string>(std::move(m.json))});
  }
}

}  // namespace foxglove
}  // namespace ucon
