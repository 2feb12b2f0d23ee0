// JSON writer and the generated JSON/jsonschema of every ucon LCM type.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "ucon/all_types.hpp"
#include "ucon/foxglove/json_writer.hpp"
#include "ucon/foxglove/lcm_json.hpp"

namespace fg = ucon::foxglove;
using nlohmann::json;

namespace {

template <class F>
std::string written(F&& f) {
  std::string s;
  fg::JsonWriter w(&s);
  f(w);
  return s;
}

template <class T>
std::vector<uint8_t> encode(const T& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

// Does `v` have the type its schema says? Numbers may be null (non-finite), as documented.
bool conforms(const json& v, const json& schema, std::string* why, const std::string& path) {
  const std::string type = schema.at("type");
  bool ok = true;
  if (type == "object") {
    ok = v.is_object();
    if (ok) {
      for (const auto& k : schema.at("required")) {
        if (!v.contains(k.get<std::string>())) {
          *why = path + ": missing " + k.get<std::string>();
          return false;
        }
      }
      for (auto it = v.begin(); it != v.end(); ++it) {
        if (!schema.at("properties").contains(it.key())) {
          *why = path + ": unexpected " + it.key();
          return false;
        }
        if (!conforms(it.value(), schema["properties"][it.key()], why, path + "." + it.key())) return false;
      }
    }
  } else if (type == "array") {
    ok = v.is_array();
    for (std::size_t i = 0; ok && i < v.size(); ++i)
      if (!conforms(v[i], schema.at("items"), why, path + "[" + std::to_string(i) + "]")) return false;
  } else if (type == "integer") {
    ok = v.is_number_integer();
  } else if (type == "number") {
    ok = v.is_number() || v.is_null();
  } else if (type == "string") {
    ok = v.is_string();
  } else if (type == "boolean") {
    ok = v.is_boolean();
  } else {
    ok = false;
  }
  if (!ok) *why = path + ": is not " + type;
  return ok;
}

}  // namespace

TEST(JsonWriter, GivenNumbersWhenWrittenThenShortestTextAndNullForNonFinite) {
  const std::string s = written([](fg::JsonWriter& w) {
    w.beginArray();
    w.number(0.1);
    w.number(0.1f);
    w.number(std::numeric_limits<double>::quiet_NaN());
    w.number(-std::numeric_limits<float>::infinity());
    w.integer(std::numeric_limits<int64_t>::min());
    w.number(1e300);
    w.number(-0.0);
    w.endArray();
  });
  EXPECT_EQ(s, "[0.1,0.1,null,null,-9223372036854775808,1e+300,-0]");
  EXPECT_TRUE(json::accept(s));
}

TEST(JsonWriter, GivenWholeArraysWhenWrittenThenTheSameTextAsElementByElement) {
  const std::vector<float> f = {1.5f, -0.1f, std::nanf(""), 3e-30f, 0.f};
  const std::vector<double> d = {1e300, -std::numeric_limits<double>::infinity(), 0.30000000000000004};
  const std::vector<int32_t> i = {0, -7, std::numeric_limits<int32_t>::max()};
  const std::vector<int64_t> l = {std::numeric_limits<int64_t>::min(), 5};
  const std::string fast = written([&](fg::JsonWriter& w) {
    w.beginArray();
    w.numberArray(f.data(), f.size());
    w.numberArray(d.data(), d.size());
    w.integerArray(i.data(), i.size());
    w.integerArray(l.data(), l.size());
    w.numberArray(f.data(), 0);
    w.endArray();
  });
  const std::string slow = written([&](fg::JsonWriter& w) {
    w.beginArray();
    for (const auto* v : {&f}) {
      w.beginArray();
      for (float x : *v) w.number(x);
      w.endArray();
    }
    w.beginArray();
    for (double x : d) w.number(x);
    w.endArray();
    w.beginArray();
    for (int32_t x : i) w.integer(x);
    w.endArray();
    w.beginArray();
    for (int64_t x : l) w.integer(x);
    w.endArray();
    w.beginArray();
    w.endArray();
    w.endArray();
  });
  EXPECT_EQ(fast, slow);
  EXPECT_EQ(fast, "[[1.5,-0.1,null,3e-30,0],[1e+300,null,0.30000000000000004],[0,-7,2147483647],"
                  "[-9223372036854775808,5],[]]");
}

TEST(JsonWriter, GivenNestedContainersWhenWrittenThenCommasAreRight) {
  const std::string s = written([](fg::JsonWriter& w) {
    w.beginObject();
    w.field("a", 1);
    w.key("b");
    w.beginArray();
    w.beginObject();
    w.endObject();
    w.beginArray();
    w.endArray();
    w.boolean(false);
    w.null();
    w.endArray();
    w.field("c", "x");
    w.endObject();
  });
  EXPECT_EQ(s, R"({"a":1,"b":[{},[],false,null],"c":"x"})");
}

TEST(JsonWriter, GivenControlQuotesAndBadUtf8WhenWrittenThenValidEscapedUtf8) {
  const std::string in = std::string("a\"b\\c\n\x01", 7) + "\xC3\xA9" + "\xFF" + "\xE2\x82";  // é kept; bad bytes replaced
  const std::string s = written([&](fg::JsonWriter& w) { w.string(in); });
  EXPECT_EQ(s, "\"a\\\"b\\\\c\\n\\u0001\xC3\xA9\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD\"");
  EXPECT_EQ(json::parse(s).get<std::string>(), "a\"b\\c\n\x01\xC3\xA9\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");
}

TEST(JsonWriter, GivenRfc4648VectorsWhenBase64ThenTheirEncodings) {
  const char* in[] = {"", "f", "fo", "foo", "foob", "fooba", "foobar"};
  const char* out[] = {"\"\"", "\"Zg==\"", "\"Zm8=\"", "\"Zm9v\"", "\"Zm9vYg==\"", "\"Zm9vYmE=\"", "\"Zm9vYmFy\""};
  for (int i = 0; i < 7; ++i) {
    const std::string s = written([&](fg::JsonWriter& w) {
      w.base64(reinterpret_cast<const uint8_t*>(in[i]), std::strlen(in[i]));
    });
    EXPECT_EQ(s, out[i]);
    EXPECT_EQ(s.size() - 2, fg::base64Length(std::strlen(in[i])));
  }
}

TEST(LcmJson, GivenEveryUconTypeWhenListedThenEachHasAValidSchemaMatchingItsDefaultMessage) {
  int types = 0;
#define UCON_COUNT(T) ++types;
  UCON_FOR_EACH_LCM_TYPE(UCON_COUNT)
#undef UCON_COUNT
  ASSERT_EQ(static_cast<int>(fg::lcmTypes().size()), types);
#define UCON_CHECK(T)                                                                                   \
  {                                                                                                     \
    const ucon::T m{};                                                                                  \
    const auto b = encode(m);                                                                           \
    const fg::LcmTypeInfo* info = fg::findLcmType(b.data(), b.size());                                  \
    ASSERT_NE(info, nullptr) << #T;                                                                     \
    EXPECT_EQ(std::string(info->name), "ucon." #T);                                                     \
    const json schema = json::parse(info->json_schema);                                                 \
    EXPECT_EQ(schema.at("title"), "ucon." #T);                                                          \
    std::string s;                                                                                      \
    fg::JsonWriter w(&s);                                                                               \
    ASSERT_TRUE(info->to_json(b.data(), static_cast<int>(b.size()), w)) << #T;                          \
    std::string why;                                                                                    \
    EXPECT_TRUE(conforms(json::parse(s), schema, &why, #T)) << why;                                     \
  }
  UCON_FOR_EACH_LCM_TYPE(UCON_CHECK)
#undef UCON_CHECK
}

TEST(LcmJson, GivenAFilledMessageWhenWrittenThenValuesNestedTypesAndBytesRoundTrip) {
  ucon::tracked_objects_t m{};
  m.utime = 1234567;
  m.valid = 1;
  m.frame_id = "world";
  m.num_objects = 1;
  ucon::tracked_object_t o{};
  o.id = 7;
  o.x = 1.5;
  o.vx = std::nan("");
  o.cov_size = 2;
  o.cov = {0.25, 1e-9};
  m.objects.push_back(o);
  const auto b = encode(m);
  std::string s;
  fg::JsonWriter w(&s);
  ASSERT_TRUE(fg::findLcmType(b.data(), b.size())->to_json(b.data(), static_cast<int>(b.size()), w));
  const json j = json::parse(s);
  EXPECT_EQ(j["utime"], 1234567);
  EXPECT_EQ(j["valid"], true);
  EXPECT_EQ(j["objects"][0]["id"], 7);
  EXPECT_EQ(j["objects"][0]["x"], 1.5);
  EXPECT_TRUE(j["objects"][0]["vx"].is_null());
  EXPECT_EQ(j["objects"][0]["cov"][1], 1e-9);
  std::string why;
  EXPECT_TRUE(conforms(j, json::parse(fg::findLcmTypeByName("ucon.tracked_objects_t")->json_schema), &why, "m")) << why;

  ucon::point_cloud_t pc{};
  pc.num_points = 2;
  pc.x = {1.f, 2.f};
  pc.y = {0.f, 0.f};
  pc.z = {0.f, 0.f};
  pc.t_offset_ns = {0, 5};
  pc.reflectivity = {0, 255};
  pc.tag = {1, 2};
  const auto pb = encode(pc);
  s.clear();
  fg::JsonWriter w2(&s);
  ASSERT_TRUE(fg::findLcmType(pb.data(), pb.size())->to_json(pb.data(), static_cast<int>(pb.size()), w2));
  const json pj = json::parse(s);
  EXPECT_EQ(pj["reflectivity"], "AP8=");  // bytes 0x00 0xFF
  EXPECT_EQ(pj["tag"], "AQI=");
  EXPECT_EQ(pj["x"][1], 2.0);
}

TEST(LcmJson, GivenTheLcmCommentsWhenSchemasAreGeneratedThenUnitsAndConstantsAreDescribed) {
  const json pose = json::parse(fg::findLcmTypeByName("ucon.robot_pose_t")->json_schema);
  EXPECT_NE(pose["properties"]["x"]["description"].get<std::string>().find("[m]"), std::string::npos);
  EXPECT_NE(pose["description"].get<std::string>().find("null"), std::string::npos);
  const json base = json::parse(fg::findLcmTypeByName("ucon.base_status_t")->json_schema);
  EXPECT_NE(base["properties"]["state"]["description"].get<std::string>().find("STATE_ESTOP = 4"), std::string::npos);
  const json cloud = json::parse(fg::findLcmTypeByName("ucon.point_cloud_t")->json_schema);
  EXPECT_EQ(cloud["properties"]["tag"]["contentEncoding"], "base64");
  EXPECT_EQ(cloud["properties"]["x"]["items"]["type"], "number");
  // A comment line of its own continues the field above it.
  const json obj = json::parse(fg::findLcmTypeByName("ucon.sim_object_t")->json_schema);
  EXPECT_NE(obj["properties"]["visible"]["description"].get<std::string>().find("evaluators"), std::string::npos);
}

TEST(LcmJson, GivenTypesWhenAskedForMessageTimeThenWallClockAndElementTypesHaveNone) {
  EXPECT_TRUE(fg::findLcmTypeByName("ucon.robot_pose_t")->has_message_time);
  EXPECT_TRUE(fg::findLcmTypeByName("ucon.process_status_t")->has_message_time);
  EXPECT_FALSE(fg::findLcmTypeByName("ucon.log_metadata_t")->has_message_time);
  EXPECT_FALSE(fg::findLcmTypeByName("ucon.supervisor_status_t")->has_message_time);
  EXPECT_FALSE(fg::findLcmTypeByName("ucon.sim_object_t")->has_message_time);
  EXPECT_EQ(fg::findLcmTypeByName("ucon.no_such_t"), nullptr);
}

TEST(LcmJson, GivenBadBytesWhenDecodedThenNothingIsWritten) {
  ucon::robot_pose_t p{};
  p.utime = 42;
  auto b = encode(p);
  EXPECT_EQ(fg::encodedUtime(b.data(), b.size()), 42);
  const fg::LcmTypeInfo* info = fg::findLcmType(b.data(), b.size());
  ASSERT_NE(info, nullptr);
  std::string s;
  fg::JsonWriter w(&s);
  EXPECT_FALSE(info->to_json(b.data(), static_cast<int>(b.size()) - 3, w));  // truncated
  EXPECT_TRUE(s.empty());
  b[0] ^= 0xFF;  // fingerprint of no ucon type
  EXPECT_EQ(fg::findLcmType(b.data(), b.size()), nullptr);
  EXPECT_EQ(fg::findLcmType(b.data(), 7), nullptr);
}
