// The Foxglove WebSocket protocol without sockets: server messages, the read-only refusals,
// subscriptions, the drop-oldest queue, and the bridge core's channels and conversions.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <set>
#include <sstream>

#include "ucon/foxglove/bridge_core.hpp"
#include "ucon/foxglove/lcm_json.hpp"
#include "ucon/foxglove/ws_protocol.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/static_points_t.hpp"

namespace fg = ucon::foxglove;
using nlohmann::json;

namespace {

fg::ViewParams params() {
  std::ifstream f("deploy/config/planner.yaml");
  std::stringstream ss;
  ss << f.rdbuf();
  std::string err;
  return fg::viewParamsFromPlannerYaml(ss.str(), "planner.yaml", &err).value();
}

template <class T>
std::vector<uint8_t> encode(const T& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

fg::OutFrame frame(std::size_t bytes, char tag) {
  fg::OutFrame f;
  f.head = std::string(bytes, tag);
  return f;
}

}  // namespace

TEST(WsProtocol, GivenSubprotocolHeadersWhenCheckedThenOnlyTheExactNameCounts) {
  EXPECT_TRUE(fg::offersSubprotocol("foxglove.websocket.v1"));
  EXPECT_TRUE(fg::offersSubprotocol("x, foxglove.websocket.v1 ,y"));
  EXPECT_FALSE(fg::offersSubprotocol("foxglove.websocket.v10"));
  EXPECT_FALSE(fg::offersSubprotocol(""));
}

TEST(WsProtocol, GivenServerMessagesWhenBuiltThenTheyFollowTheProtocol) {
  const json info = json::parse(fg::serverInfoJson("ucon", "42"));
  EXPECT_EQ(info["op"], "serverInfo");
  EXPECT_EQ(info["capabilities"], json::array({"time"}));  // nothing a client could write with
  EXPECT_EQ(info["sessionId"], "42");
  fg::WsChannel c;
  c.id = 3;
  c.topic = "/tf";
  c.schema_name = "foxglove.FrameTransform";
  c.schema = "{}";
  const json adv = json::parse(fg::advertiseJson({c}));
  EXPECT_EQ(adv["op"], "advertise");
  EXPECT_EQ(adv["channels"][0]["id"], 3);
  EXPECT_EQ(adv["channels"][0]["encoding"], "json");
  EXPECT_EQ(adv["channels"][0]["schemaEncoding"], "jsonschema");
  const json st = json::parse(fg::statusJson(fg::StatusLevel::kError, std::string("bad \xFF", 5)));
  EXPECT_EQ(st["level"], 2);

  const std::string h = fg::messageDataHeader(0x01020304u, 0x1122334455667788ull);
  ASSERT_EQ(h.size(), 13u);
  EXPECT_EQ(h[0], 0x01);
  EXPECT_EQ(h.substr(1, 4), std::string("\x04\x03\x02\x01", 4));
  EXPECT_EQ(h.substr(5, 8), std::string("\x88\x77\x66\x55\x44\x33\x22\x11", 8));
  const std::string t = fg::timeMessage(5);
  ASSERT_EQ(t.size(), 9u);
  EXPECT_EQ(t[0], 0x02);
  EXPECT_EQ(t[1], 5);
}

TEST(WsProtocol, GivenClientRequestsWhenParsedThenOnlySubscriptionsAreAccepted) {
  auto r = fg::parseClientText(R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":3},{"id":1,"channelId":5}]})");
  ASSERT_EQ(r.kind, fg::ClientRequest::Kind::kSubscribe);
  EXPECT_EQ(r.subscribe.size(), 2u);
  EXPECT_EQ(r.subscribe[1], std::make_pair(1u, 5u));
  r = fg::parseClientText(R"({"op":"unsubscribe","subscriptionIds":[1]})");
  ASSERT_EQ(r.kind, fg::ClientRequest::Kind::kUnsubscribe);
  EXPECT_EQ(r.unsubscribe, std::vector<uint32_t>{1});
  for (const char* op : {"advertise", "unadvertise", "getParameters", "setParameters", "subscribeParameterUpdates",
                         "unsubscribeParameterUpdates", "subscribeConnectionGraph", "fetchAsset", "callService"}) {
    r = fg::parseClientText(std::string(R"({"op":")") + op + R"("})");
    EXPECT_EQ(r.kind, fg::ClientRequest::Kind::kRefused) << op;
    EXPECT_NE(r.error.find("read-only"), std::string::npos) << op;
  }
  for (const char* bad : {"", "[1]", R"({"op":1})", R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":2}]})",
                          R"({"op":"subscribe"})", R"({"op":"unsubscribe","subscriptionIds":["a"]})", "{\"op\":"}) {
    EXPECT_EQ(fg::parseClientText(bad).kind, fg::ClientRequest::Kind::kInvalid) << bad;
  }
  const uint8_t publish[] = {0x01, 0, 0, 0, 0, '{', '}'};
  EXPECT_NE(fg::refuseClientBinary(publish, sizeof(publish)).find("read-only"), std::string::npos);
  const uint8_t call[] = {0x02, 1};
  EXPECT_NE(fg::refuseClientBinary(call, sizeof(call)).find("service"), std::string::npos);
}

TEST(WsProtocol, GivenSubscriptionsWhenAppliedThenIdsAndChannelsAreUnique) {
  std::map<uint32_t, fg::WsChannel> channels;
  channels[1].id = 1;
  channels[2].id = 2;
  fg::ClientSubscriptions s;
  std::vector<uint32_t> added, removed;
  auto errors = s.subscribe({{10, 1}, {10, 2}, {11, 9}, {12, 1}, {13, 2}}, channels, &added);
  EXPECT_EQ(added, (std::vector<uint32_t>{1, 2}));
  ASSERT_EQ(errors.size(), 3u);  // id 10 reused, channel 9 unknown, channel 1 twice
  EXPECT_EQ(*s.subscriptionFor(2), 13u);
  errors = s.unsubscribe({10, 99}, &removed);
  EXPECT_EQ(removed, std::vector<uint32_t>{1});
  EXPECT_EQ(errors.size(), 1u);
  EXPECT_FALSE(s.subscriptionFor(1).has_value());
  EXPECT_EQ(s.channels(), std::vector<uint32_t>{2});
}

TEST(WsProtocol, GivenAFullQueueWhenPushedThenTheOldestAreDroppedAndCounted) {
  fg::DropOldestQueue q(3, 1000);
  for (char c = 'a'; c <= 'e'; ++c) q.push(frame(10, c));
  EXPECT_EQ(q.size(), 3u);
  EXPECT_EQ(q.dropped(), 2u);
  EXPECT_EQ(q.pop()->head[0], 'c');  // the newest three remain, oldest first
  EXPECT_EQ(q.bytes(), 20u);
  // Byte bound: 900 bytes fit beside the 20 queued; 200 more do not: the frame bound drops
  // d, the byte bound e and x.
  EXPECT_EQ(q.push(frame(900, 'x')), 0u);
  EXPECT_EQ(q.push(frame(200, 'y')), 3u);
  EXPECT_EQ(q.size(), 1u);
  EXPECT_EQ(q.bytes(), 200u);
  // A frame larger than the bound on its own is kept, alone.
  EXPECT_EQ(q.push(frame(5000, 'z')), 1u);
  EXPECT_EQ(q.size(), 1u);
  EXPECT_EQ(q.dropped(), 6u);
  EXPECT_EQ(q.pop()->head[0], 'z');
  EXPECT_FALSE(q.pop().has_value());
  EXPECT_EQ(q.bytes(), 0u);
}

TEST(BridgeCore, GivenTheRuntimeChannelsWhenStartedThenTheyAreAdvertisedWithTheirViews) {
  fg::BridgeCore core(params());
  const auto channels = core.takeNewChannels();
  std::map<std::string, std::string> schema_of;
  for (const auto& c : channels) schema_of[c.topic] = c.schema_name;
  EXPECT_EQ(schema_of["LIDAR_POINTS"], "ucon.point_cloud_t");
  EXPECT_EQ(schema_of["/lidar_points"], "foxglove.PointCloud");
  EXPECT_EQ(schema_of["/tf"], "foxglove.FrameTransform");
  EXPECT_EQ(schema_of["/perception_objects"], "foxglove.SceneUpdate");
  EXPECT_EQ(schema_of["/map"], "foxglove.Grid");
  EXPECT_EQ(schema_of["PROC_STATUS"], "ucon.supervisor_status_t");
  EXPECT_TRUE(core.takeNewChannels().empty());
  // Ids are unique and start at 1.
  std::set<uint32_t> ids;
  for (const auto& c : channels) ids.insert(c.id);
  EXPECT_EQ(ids.size(), channels.size());
  EXPECT_EQ(*ids.begin(), 1u);
}

TEST(BridgeCore, GivenSubscriptionsWhenMessagesArriveThenOnlyWantedChannelsAreConverted) {
  fg::BridgeCore core(params());
  std::map<std::string, uint32_t> id;
  for (const auto& c : core.takeNewChannels()) id[c.topic] = c.id;
  ucon::robot_pose_t p{};
  p.utime = 7'000'000;
  p.valid = 1;
  p.qw = 1.0;
  const auto b = encode(p);
  std::vector<fg::BridgeOutput> out;
  core.onLcm("ROBOT_POSE", b.data(), b.size(), [](uint32_t) { return false; }, &out);
  EXPECT_TRUE(out.empty());
  core.onLcm("ROBOT_POSE", b.data(), b.size(), [&](uint32_t c) { return c == id["/tf"]; }, &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].channel_id, id["/tf"]);
  EXPECT_EQ(out[0].timestamp_ns, 7'000'000'000ull);
  EXPECT_EQ(json::parse(*out[0].payload)["child_frame_id"], "base");
  EXPECT_EQ(core.nowNs(), 7'000'000'000ull);

  // A ucon channel nobody declared: registered and advertised on first sight.
  out.clear();
  core.onLcm("OTHER_POSE", b.data(), b.size(), [](uint32_t) { return true; }, &out);
  const auto fresh = core.takeNewChannels();
  ASSERT_EQ(fresh.size(), 2u);
  EXPECT_EQ(fresh[0].topic, "OTHER_POSE");
  EXPECT_EQ(fresh[1].topic, "/other_pose");
  EXPECT_EQ(out.size(), 2u);  // raw, /other_pose (only ROBOT_POSE moves the base frame on /tf)
  // Not a ucon type: counted.
  std::vector<uint8_t> junk(20, 0xAB);
  core.onLcm("JUNK", junk.data(), junk.size(), [](uint32_t) { return true; }, &out);
  EXPECT_EQ(core.stats().unknown_type, 1);
}

TEST(BridgeCore, GivenStaticPointsWithoutSubscribersWhenLaterAskedThenTheMapHasThem) {
  fg::BridgeCore core(params());
  std::map<std::string, uint32_t> id;
  for (const auto& c : core.takeNewChannels()) id[c.topic] = c.id;
  ucon::static_points_t s{};
  s.utime = 1'000'000;
  s.valid = 1;
  s.num_points = 1;
  s.x = {1.0f};
  s.y = {1.0f};
  s.z = {0.3f};
  const auto b = encode(s);
  std::vector<fg::BridgeOutput> out;
  core.onLcm("PERCEPTION_STATIC", b.data(), b.size(), [](uint32_t) { return false; }, &out);
  EXPECT_TRUE(out.empty());
  core.currentMap(&out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].channel_id, id["/map"]);
  EXPECT_EQ(json::parse(*out[0].payload)["column_count"], 1);
}
