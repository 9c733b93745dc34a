#include "ovpc/controller/bicycle_model.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace ovpc::controller {
namespace {

TEST(BicycleModelTest, DrivesStraightAndAcceleratesWithinTheLimit) {
  const BicycleModel model(BicycleModel::Config{});  // 1 m/s^2
  BicycleModel::State s;
  s.pose.yaw_rad = kPi / 2;
  for (int i = 0; i < 50; ++i) s = model.Step(s, Command{0.0, 2.0, false}, 0.01);
  EXPECT_NEAR(s.speed_mps, 0.5, 1e-9);
  EXPECT_NEAR(s.pose.y_m, 0.5 * 1.0 * 0.5 * 0.5, 1e-9);  // a t^2 / 2
  EXPECT_NEAR(s.pose.x_m, 0.0, 1e-9);
}

TEST(BicycleModelTest, TurnsOnTheCircleOfItsSteeringAngle) {
  const BicycleModel::Config config;
  const BicycleModel model(config);
  const double steering = DegToRad(20.0);
  const double radius = config.wheelbase_m / std::tan(steering);
  BicycleModel::State s;
  s.speed_mps = 1.0;
  s.steering_rad = steering;
  for (int i = 0; i < 2000; ++i) {
    s = model.Step(s, Command{steering, 1.0, false}, 0.01);
    ASSERT_NEAR(std::hypot(s.pose.x_m, s.pose.y_m - radius), radius, 1e-9);  // centre on the left
  }
  // Backwards on the same circle, turning the other way.
  const double yaw = s.pose.yaw_rad;
  for (int i = 0; i < 300; ++i) s = model.Step(s, Command{steering, -1.0, false}, 0.01);
  EXPECT_NEAR(std::hypot(s.pose.x_m, s.pose.y_m - radius), radius, 1e-9);
  EXPECT_LT(std::remainder(s.pose.yaw_rad - yaw, 2 * kPi), 0.0);
}

TEST(BicycleModelTest, SteeringRateAndStopAreLimited) {
  BicycleModel::Config config;
  config.max_steering_rate_radps = 1.0;
  const BicycleModel model(config);
  BicycleModel::State s;
  s = model.Step(s, Command{1.0, 0.0, false}, 0.1);
  EXPECT_NEAR(s.steering_rad, 0.1, 1e-12);
  for (int i = 0; i < 100; ++i) s = model.Step(s, Command{1.0, 0.0, false}, 0.1);
  EXPECT_NEAR(s.steering_rad, config.max_steering_rad, 1e-12);
  config.wheelbase_m = 0.0;
  EXPECT_THROW(BicycleModel{config}, std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::controller
