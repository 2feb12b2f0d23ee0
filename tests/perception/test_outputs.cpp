// Perception's messages (outputs.hpp): one object estimate to tracked_object_t and back, and
// the validity of PERCEPTION_OBJECTS / PERCEPTION_STATIC.
#include <gtest/gtest.h>

#include "ucon/perception/outputs.hpp"

using namespace ucon::perception;
using TO = ucon::tracked_object_t;

TEST(Outputs, GivenAnEstimateThenTheMessageCarriesItsStateAndTheFullRowMajorCovariance) {
  ObjectEstimate e;
  e.id = 7;
  e.state = TO::STATE_COASTING;
  e.last_association = TO::ASSOC_REASSOCIATED;
  e.x << 1, 2, 3, 4, 5, 6;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) e.P(r, c) = 10 * r + c;  // not symmetric: row-major order shows
  e.size << 0.4, 0.005, 1.7;
  e.num_points = 12;
  e.age_frames = 30;
  e.frames_since_seen = 2;
  const TO t = toMessage(e);
  EXPECT_EQ(t.id, 7);
  EXPECT_EQ(t.state, TO::STATE_COASTING);
  EXPECT_EQ(t.last_association, TO::ASSOC_REASSOCIATED);
  EXPECT_EQ(t.x, 1.0);
  EXPECT_EQ(t.y, 2.0);
  EXPECT_EQ(t.z, 3.0);
  EXPECT_EQ(t.vx, 4.0);
  EXPECT_EQ(t.vy, 5.0);
  EXPECT_EQ(t.vz, 6.0);
  ASSERT_EQ(t.cov_size, 36);
  ASSERT_EQ(t.cov.size(), 36u);
  EXPECT_EQ(t.cov[1], 1.0);   // row 0, column 1
  EXPECT_EQ(t.cov[6], 10.0);  // row 1, column 0
  EXPECT_EQ(t.cov[21], 33.0);  // vx variance
  EXPECT_EQ(t.size_x, 0.4);
  EXPECT_EQ(t.size_y, 0.01);  // floored
  EXPECT_EQ(t.size_z, 1.7);
  EXPECT_EQ(t.yaw, 0.0);
  EXPECT_EQ(t.num_points, 12);
  EXPECT_EQ(t.age_frames, 30);
  EXPECT_EQ(t.frames_since_seen, 2);
  ucon::kalman::Cov6 back;
  ASSERT_TRUE(covarianceOf(t, &back));
  EXPECT_TRUE(back == e.P);
}

TEST(Outputs, GivenAMessageWithoutCovarianceThenCovarianceOfSaysSo) {
  TO t{};
  t.cov_size = 0;
  ucon::kalman::Cov6 P = ucon::kalman::Cov6::Identity();
  EXPECT_FALSE(covarianceOf(t, &P));
  t.cov_size = 36;  // claims 36, carries fewer
  t.cov.assign(6, 1.0);
  EXPECT_FALSE(covarianceOf(t, &P));
  EXPECT_TRUE(P == ucon::kalman::Cov6::Identity());
}

TEST(Outputs, GivenObjectsThenTheMessageIsValidInTheWorldFrameAndTheInvalidOnesAreEmpty) {
  const auto o = objectsMessage(5, 3, 9, {toMessage({}), toMessage({})});
  EXPECT_EQ(o.utime, 5);
  EXPECT_EQ(o.seq, 3);
  EXPECT_EQ(o.frame_seq, 9);
  EXPECT_TRUE(o.valid);
  EXPECT_EQ(o.frame_id, "world");
  EXPECT_EQ(o.num_objects, 2);
  const auto bad = invalidObjects(6, 4, -1);
  EXPECT_FALSE(bad.valid);
  EXPECT_EQ(bad.num_objects, 0);
  EXPECT_EQ(bad.frame_seq, -1);
  EXPECT_EQ(bad.frame_id, "world");
}

TEST(Outputs, GivenPointsAndADynamicMaskThenTheStaticMessageHoldsTheOthers) {
  const std::vector<Eigen::Vector3f> pts{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
  const auto s = staticMessage(5, 2, {0.1, 0.2, 0.5}, 15.0, pts, {0, 1, 0});
  EXPECT_TRUE(s.valid);
  ASSERT_EQ(s.num_points, 2);
  EXPECT_EQ(s.x[0], 1.0f);
  EXPECT_EQ(s.x[1], 7.0f);
  EXPECT_EQ(s.z[1], 9.0f);
  EXPECT_EQ(s.origin_z, 0.5);
  EXPECT_EQ(s.max_range, 15.0f);
  const auto bad = invalidStatic(6, 3, 15.0);
  EXPECT_FALSE(bad.valid);
  EXPECT_EQ(bad.num_points, 0);
  EXPECT_EQ(bad.max_range, 15.0f);
}
