#include "ucon/foxglove/ws_protocol.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>

namespace ucon {
namespace foxglove {

namespace {

void putLe(std::string* s, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s->push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

// A JSON number that is an integer in [0, 2^32).
bool asUint32(const nlohmann::json& v, uint32_t* out) {
  if (!v.is_number_integer() && !v.is_number_unsigned()) return false;
  if (v.is_number_unsigned()) {
    const auto u = v.get<uint64_t>();
    if (u > 0xFFFFFFFFull) return false;
    *out = static_cast<uint32_t>(u);
    return true;
  }
  const auto i = v.get<int64_t>();
  if (i < 0 || i > 0xFFFFFFFFll) return false;
  *out = static_cast<uint32_t>(i);
  return true;
}

}  // namespace

bool offersSubprotocol(const std::string& header_value) {
  std::size_t start = 0;
  while (start <= header_value.size()) {
    const std::size_t comma = header_value.find(',', start);
    const std::string item = trim(header_value.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (item == kSubprotocol) return true;
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return false;
}

std::string serverInfoJson(const std::string& name, const std::string& instance_id) {
  nlohmann::json j = {{"op", "serverInfo"},
                      {"name", name},
                      {"capabilities", {"time"}},
                      {"metadata", {{"read_only", "true"}}},
                      // The protocol names the server instance's id "sessionId".
                      {"sessionId", instance_id}};
  return j.dump();
}

std::string advertiseJson(const std::vector<WsChannel>& channels) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : channels) {
    list.push_back({{"id", c.id},
                    {"topic", c.topic},
                    {"encoding", c.encoding},
                    {"schemaName", c.schema_name},
                    {"schema", c.schema},
                    {"schemaEncoding", c.schema_encoding}});
  }
  return nlohmann::json{{"op", "advertise"}, {"channels", std::move(list)}}.dump();
}

std::string statusJson(StatusLevel level, const std::string& message) {
  // dump() with replace: a message quoting a client's bad bytes stays valid UTF-8.
  return nlohmann::json{{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}.dump(
      -1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string messageDataHeader(uint32_t subscription_id, uint64_t timestamp_ns) {
  std::string h;
  h.reserve(13);
  h.push_back(0x01);
  putLe(&h, subscription_id, 4);
  putLe(&h, timestamp_ns, 8);
  return h;
}

std::string timeMessage(uint64_t timestamp_ns) {
  std::string h;
  h.reserve(9);
  h.push_back(0x02);
  putLe(&h, timestamp_ns, 8);
  return h;
}

ClientRequest parseClientText(const std::string& text) {
  ClientRequest r;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    r.error = "not a JSON object";
    return r;
  }
  const auto op = j.find("op");
  if (op == j.end() || !op->is_string()) {
    r.error = "no \"op\" string";
    return r;
  }
  r.op = op->get<std::string>();
  if (r.op == "subscribe") {
    const auto subs = j.find("subscriptions");
    if (subs == j.end() || !subs->is_array()) {
      r.error = "subscribe without a \"subscriptions\" array";
      return r;
    }
    for (const auto& s : *subs) {
      uint32_t id = 0, channel = 0;
      if (!s.is_object() || !s.contains("id") || !s.contains("channelId") || !asUint32(s["id"], &id) ||
          !asUint32(s["channelId"], &channel)) {
        r.error = "subscribe: each subscription needs integer \"id\" and \"channelId\"";
        r.subscribe.clear();
        return r;
      }
      r.subscribe.emplace_back(id, channel);
    }
    r.kind = ClientRequest::Kind::kSubscribe;
    return r;
  }
  if (r.op == "unsubscribe") {
    const auto ids = j.find("subscriptionIds");
    if (ids == j.end() || !ids->is_array()) {
      r.error = "unsubscribe without a \"subscriptionIds\" array";
      return r;
    }
    for (const auto& v : *ids) {
      uint32_t id = 0;
      if (!asUint32(v, &id)) {
        r.error = "unsubscribe: subscription ids must be integers";
        r.unsubscribe.clear();
        return r;
      }
      r.unsubscribe.push_back(id);
    }
    r.kind = ClientRequest::Kind::kUnsubscribe;
    return r;
  }
  r.kind = ClientRequest::Kind::kRefused;
  if (r.op == "advertise" || r.op == "unadvertise") {
    r.error = "this bridge is read-only: clients cannot publish ('" + r.op + "' refused)";
  } else if (r.op == "getParameters" || r.op == "setParameters" || r.op == "subscribeParameterUpdates" ||
             r.op == "unsubscribeParameterUpdates") {
    r.error = "this bridge is read-only: it has no parameters ('" + r.op + "' refused)";
  } else {
    r.error = "this bridge is read-only and does not support '" + r.op + "'";
  }
  return r;
}

std::string refuseClientBinary(const uint8_t* data, std::size_t size) {
  if (size == 0) return "empty binary message";
  switch (data[0]) {
    case 0x01: return "this bridge is read-only: clients cannot publish (message data refused)";
    case 0x02: return "this bridge is read-only: it offers no services (service call refused)";
    default: return "unknown binary opcode " + std::to_string(data[0]);
  }
}

std::vector<std::string> ClientSubscriptions::subscribe(const std::vector<std::pair<uint32_t, uint32_t>>& requests,
                                                        const std::map<uint32_t, WsChannel>& channels,
                                                        std::vector<uint32_t>* added) {
  std::vector<std::string> errors;
  for (const auto& [id, channel] : requests) {
    if (by_subscription_.count(id)) {
      errors.push_back("subscription id " + std::to_string(id) + " is already in use");
    } else if (!channels.count(channel)) {
      errors.push_back("channel " + std::to_string(channel) + " is not advertised");
    } else if (by_channel_.count(channel)) {
      errors.push_back("already subscribed to channel " + std::to_string(channel));
    } else {
      by_subscription_[id] = channel;
      by_channel_[channel] = id;
      if (added) added->push_back(channel);
    }
  }
  return errors;
}

std::vector<std::string> ClientSubscriptions::unsubscribe(const std::vector<uint32_t>& ids,
                                                          std::vector<uint32_t>* removed) {
  std::vector<std::string> errors;
  for (uint32_t id : ids) {
    const auto it = by_subscription_.find(id);
    if (it == by_subscription_.end()) {
      errors.push_back("no subscription " + std::to_string(id));
      continue;
    }
    if (removed) removed->push_back(it->second);
    by_channel_.erase(it->second);
    by_subscription_.erase(it);
  }
  return errors;
}

std::optional<uint32_t> ClientSubscriptions::subscriptionFor(uint32_t channel_id) const {
  const auto it = by_channel_.find(channel_id);
  if (it == by_channel_.end()) return std::nullopt;
  return it->second;
}

std::vector<uint32_t> ClientSubscriptions::channels() const {
  std::vector<uint32_t> out;
  for (const auto& [channel, id] : by_channel_) out.push_back(channel);
  return out;
}

std::size_t DropOldestQueue::push(OutFrame f) {
  std::size_t dropped = 0;
  const std::size_t n = f.size();
  while (!frames_.empty() && (frames_.size() + 1 > max_frames_ || bytes_ + n > max_bytes_)) {
    bytes_ -= frames_.front().size();
    frames_.pop_front();
    ++dropped;
  }
  bytes_ += n;
  frames_.push_back(std::move(f));
  dropped_ += dropped;
  return dropped;
}

std::optional<OutFrame> DropOldestQueue::pop() {
  if (frames_.empty()) return std::nullopt;
  OutFrame f = std::move(frames_.front());
  frames_.pop_front();
  bytes_ -= f.size();
  return f;
}

}  // namespace foxglove
}  // namespace ucon
