#include "service/geometry/corner_motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace monocle {
namespace {

CornerPose PoseAt(double t) {  // constant velocity, pan crossing the +-pi seam at t = 1
  return CornerPose{1.0 + 0.5 * t, 2.0 - 0.3 * t, 1.6, std::numbers::pi - 0.2 + 0.2 * t,
                    0.9 + 0.1 * t, 0.02 * t};
}

TEST(CornerMotionTest, NothingBeforeTheFirstPoseThenThatPoseWithAWideSigma) {
  CornerMotionModel model;
  EXPECT_FALSE(model.Predict(0.0));
  model.Update(PoseAt(0), 0.0);
  const auto p = model.Predict(0.1);
  ASSERT_TRUE(p);
  EXPECT_FALSE(p->has_velocity);
  EXPECT_NEAR(p->pose.x_m, 1.0, 1e-12);
  EXPECT_NEAR(p->sigma(0), 0.1 * CornerMotionOptions{}.static_m_per_s, 1e-12);
}

TEST(CornerMotionTest, ConstantVelocityIsPredictedExactlyAcrossTheAngleSeam) {
  CornerMotionModel model;
  for (int i = 0; i < 8; ++i) model.Update(PoseAt(0.25 * i), 0.25 * i);
  const auto p = model.Predict(2.0);
  ASSERT_TRUE(p && p->has_velocity);
  const PoseVector miss = PoseDifference(p->pose, PoseAt(2.0));
  EXPECT_LT(miss.norm(), 1e-9) << miss.transpose();
  // Smooth motion: the sigma is the floor, over the 0.25 s predicted.
  EXPECT_NEAR(p->sigma(0), 0.25 * CornerMotionOptions{}.floor_m_per_s, 1e-9);
}

TEST(CornerMotionTest, AJoltWidensTheSigmaToTheMiss) {
  CornerMotionModel model;
  const double dt = 1.0 / 30;
  for (int i = 0; i < 5; ++i) model.Update(PoseAt(dt * i), dt * i);
  CornerPose jolted = PoseAt(5 * dt);
  jolted.pan_rad += 0.05;  // 3 degrees off the constant-velocity path in one frame
  model.Update(jolted, 5 * dt);
  const auto p = model.Predict(6 * dt);
  ASSERT_TRUE(p);
  // The misses so far were 0: the jolt enters the running RMS with its weight.
  const double w = CornerMotionOptions{}.innovation_weight;
  EXPECT_NEAR(p->sigma(2), 0.05 * std::sqrt(w), 1e-9);
  EXPECT_NEAR(p->sigma(0), dt * CornerMotionOptions{}.floor_m_per_s, 1e-9);
}

TEST(CornerMotionTest, TimeGoingBackwardsStartsTheVelocityAgain) {
  CornerMotionModel model;
  model.Update(PoseAt(0), 1.0);
  model.Update(PoseAt(1), 2.0);
  model.Update(PoseAt(2), 1.5);
  const auto p = model.Predict(1.6);
  ASSERT_TRUE(p);
  EXPECT_FALSE(p->has_velocity);
}

}  // namespace
}  // namespace monocle
