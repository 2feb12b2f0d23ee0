// Every message type round-trips through encode/decode: empty, filled, and a 100 000-point
// cloud (larger than any frame the Mid-360 produces at 10 Hz).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ucon/all_types.hpp"

namespace {

template <class Msg>
std::vector<uint8_t> encode(const Msg& m) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  const int n = m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  EXPECT_EQ(n, static_cast<int>(buf.size()));
  return buf;
}

// Encodes, decodes into a fresh message, encodes again: the bytes must be identical and the
// decoder must consume exactly what the encoder wrote.
template <class Msg>
Msg roundTrip(const Msg& m) {
  const auto a = encode(m);
  Msg d;
  const int used = d.decode(a.data(), 0, static_cast<int>(a.size()));
  EXPECT_EQ(used, static_cast<int>(a.size()));
  EXPECT_EQ(encode(d), a);
  return d;
}

}  // namespace

TEST(LcmTypes, GivenDefaultMessagesWithEmptyArraysThenEveryTypeRoundTrips) {
#define UCON_RT(T)                                      \
  {                                                     \
    ucon::T m{};                                        \
    SCOPED_TRACE(#T);                                   \
    roundTrip(m);                                       \
  }
  UCON_FOR_EACH_LCM_TYPE(UCON_RT)
#undef UCON_RT
}

TEST(LcmTypes, GivenTruncatedBufferThenDecodeFailsInsteadOfReadingPastTheEnd) {
  ucon::point_cloud_t m{};
  m.num_points = 3;
  m.x = m.y = m.z = {1, 2, 3};
  m.t_offset_ns = {0, 1, 2};
  m.reflectivity = m.tag = {0, 0, 0};
  auto buf = encode(m);
  ucon::point_cloud_t d;
  EXPECT_LT(d.decode(buf.data(), 0, static_cast<int>(buf.size()) - 5), 0);
}

TEST(LcmTypes, GivenAHundredThousandPointCloudThenItRoundTripsExactly) {
  ucon::point_cloud_t m{};
  m.utime = 1700000000123456;
  m.seq = 42;
  m.frame_id = "base";
  m.time_sync = ucon::point_cloud_t::TIME_PTP;
  m.num_points = 100000;
  for (int i = 0; i < m.num_points; ++i) {
    m.x.push_back(0.001f * i);
    m.y.push_back(-0.002f * i);
    m.z.push_back(std::sin(0.01f * i));
    m.t_offset_ns.push_back(i * 1000);
    m.reflectivity.push_back(static_cast<uint8_t>(i % 256));
    m.tag.push_back(static_cast<uint8_t>(i % 3));
  }
  const auto d = roundTrip(m);
  ASSERT_EQ(d.num_points, 100000);
  EXPECT_EQ(d.x[99999], m.x[99999]);
  EXPECT_EQ(d.t_offset_ns[12345], 12345000);
  EXPECT_EQ(d.reflectivity[300], 300 % 256);
  EXPECT_EQ(d.frame_id, "base");
}

TEST(LcmTypes, GivenNestedObjectsWithCovarianceThenTheyRoundTrip) {
  ucon::tracked_objects_t m{};
  m.utime = 5;
  m.valid = true;
  for (int k = 0; k < 3; ++k) {
    ucon::tracked_object_t o{};
    o.id = k + 1;
    o.state = ucon::tracked_object_t::STATE_CONFIRMED;
    o.cov_size = 36;
    o.cov.assign(36, 0.0);
    for (int i = 0; i < 6; ++i) o.cov[i * 6 + i] = 0.1 * (i + 1);
    o.size_x = 0.5;
    m.objects.push_back(o);
  }
  m.num_objects = 3;
  const auto d = roundTrip(m);
  ASSERT_EQ(d.objects.size(), 3u);
  EXPECT_EQ(d.objects[2].id, 3);
  EXPECT_DOUBLE_EQ(d.objects[1].cov[35], 0.6);
}

TEST(LcmTypes, GivenATrajectoryAndAStatusThenTheyRoundTrip) {
  ucon::trajectory_t t{};
  t.num_pieces = 2;
  t.durations = {0.5, 0.7};
  t.dim = 2;
  t.order1 = 6;
  t.num_coeffs = 24;
  for (int i = 0; i < 24; ++i) t.coeffs.push_back(i * 0.5);
  t.yaw = std::nan("");
  t.message = "ok";
  const auto dt = roundTrip(t);
  EXPECT_EQ(dt.coeffs[23], 11.5);
  EXPECT_TRUE(std::isnan(dt.yaw));

  ucon::process_status_t s{};
  s.name = "perception";
  s.num_counters = 2;
  s.counter_names = {"frames", "drops"};
  s.counter_values = {10, 1};
  s.num_timings = 1;
  s.timing_names = {"cluster"};
  s.timing_median_ms = {1.5};
  s.timing_max_ms = {3.0};
  const auto ds = roundTrip(s);
  EXPECT_EQ(ds.counter_names[1], "drops");
  EXPECT_EQ(ds.timing_max_ms[0], 3.0);

  ucon::supervisor_status_t sup{};
  ucon::proc_info_t p{};
  p.name = "planner";
  p.pid = 1234;
  sup.procs = {p, p};
  sup.num_procs = 2;
  EXPECT_EQ(roundTrip(sup).procs[1].pid, 1234);
}

#include "ucon/fields.hpp"

TEST(LcmFields, GivenAnEncodedMessageThenItsFieldsAreListedByNameAndADifferenceIsNamed) {
  ucon::tracked_objects_t a{};
  a.utime = 10;
  a.valid = true;
  ucon::tracked_object_t o{};
  o.id = 4;
  o.cov_size = 2;
  o.cov = {0.5, 0.25};
  a.objects = {o, o};
  a.num_objects = 2;
  ucon::tracked_objects_t b = a;
  b.objects[1].cov[1] = 0.3;
  auto bytes = [](const ucon::tracked_objects_t& m) {
    std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    return buf;
  };
  const auto ba = bytes(a), bb = bytes(b);
  std::string ta, tb;
  ucon::FieldList fa, fb;
  ASSERT_TRUE(ucon::decodeFields(ba.data(), static_cast<int>(ba.size()), &ta, &fa));
  ASSERT_TRUE(ucon::decodeFields(bb.data(), static_cast<int>(bb.size()), &tb, &fb));
  EXPECT_EQ(ta, "ucon.tracked_objects_t");
  ASSERT_EQ(fa.size(), fb.size());
  std::string first_diff;
  for (std::size_t i = 0; i < fa.size() && first_diff.empty(); ++i) {
    if (fa[i].second != fb[i].second) first_diff = fa[i].first;
  }
  EXPECT_EQ(first_diff, "objects[1].cov[1]");
  EXPECT_EQ(fa[0].first, "utime");
  EXPECT_EQ(fa[0].second, "10");
  // Unknown fingerprint or garbage: false, no crash.
  std::vector<uint8_t> junk(16, 0xAB);
  std::string t;
  ucon::FieldList f;
  EXPECT_FALSE(ucon::decodeFields(junk.data(), static_cast<int>(junk.size()), &t, &f));
  EXPECT_FALSE(ucon::decodeFields(ba.data(), static_cast<int>(ba.size()) - 3, &t, &f));
}

TEST(LcmFields, GivenEveryTypeThenTheFieldListStartsWithUtimeForTopLevelMessages) {
  int checked = 0;
#define UCON_FIELDS(T)                                              \
  {                                                                 \
    ucon::T m{};                                                    \
    ucon::FieldList f;                                              \
    ucon::fields(m, "", f);                                         \
    ASSERT_FALSE(f.empty()) << #T;                                  \
    if (f[0].first == "utime") {                                    \
      ++checked;                                                    \
      EXPECT_EQ(f[1].first, "seq") << #T " must carry seq after utime"; \
    }                                                               \
  }
  UCON_FOR_EACH_LCM_TYPE(UCON_FIELDS)
#undef UCON_FIELDS
  EXPECT_GE(checked, 14);
}
