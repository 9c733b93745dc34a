// The path-follower seam: a planned path and the odometry pose in, a command out.
#pragma once

#include <optional>

#include "ovpc/controller/command.h"
#include "ovpc/controller/pure_pursuit.h"
#include "ovpc/planner/path.h"

namespace ovpc::navigation {

/// One narrow job: follow the current path. Paths and poses are in the odometry frame O; the pose
/// is the rear axle's. The navigator calls Update at its control rate while a path is set and
/// commands a stop otherwise.
class PathFollower {
 public:
  virtual ~PathFollower() = default;
  /// Follows `path_O` from its start, replacing any path before it.
  virtual void Follow(const planner::Path& path_O) = 0;
  /// Drops the path (the vehicle is told to stand).
  virtual void Clear() = 0;
  virtual bool has_path() const = 0;
  /// The end of the current path is reached.
  virtual bool done() const = 0;
  /// The command at `pose_O` moving at `speed_mps` (signed, forward positive).
  virtual controller::Command Update(const planner::Pose2& pose_O, double speed_mps) = 0;
};

/// Pure pursuit (controller::PurePursuit), a fresh follower per path.
class PurePursuitFollower final : public PathFollower {
 public:
  /// @throws std::invalid_argument for an invalid config.
  explicit PurePursuitFollower(const controller::PurePursuit::Config& config,
                               const controller::SteeringGeometry& steering = {})
      : config_(config), steering_(steering) {
    config_.Validate();
    steering_.Validate();
  }
  void Follow(const planner::Path& path_O) override { follower_.emplace(config_, path_O, steering_); }
  void Clear() override { follower_.reset(); }
  bool has_path() const override { return follower_.has_value(); }
  bool done() const override { return follower_ && follower_->done(); }
  controller::Command Update(const planner::Pose2& pose_O, double speed_mps) override {
    if (!follower_) return controller::Command{0.0, 0.0, true};
    return follower_->Update(pose_O, speed_mps);
  }

 private:
  controller::PurePursuit::Config config_;
  controller::SteeringGeometry steering_;
  std::optional<controller::PurePursuit> follower_;
};

}  // namespace ovpc::navigation
