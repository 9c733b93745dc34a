// Planar poses and the planner's output path; the controller follows it.
#pragma once

#include <cstddef>
#include <vector>

#include "ovpc/core/types.h"

namespace ovpc::planner {

/// Distance from p to the segment [a, b] in the plane.
double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

/// Yaw wrapped to [-pi, pi). OMPL's SO(2) bounds exclude +pi, so every yaw handed to OMPL and every
/// yaw the planner returns goes through this.
double NormalizeYaw(double yaw_rad);

/// A pose in the horizontal plane of the map frame L (gravity-aligned, z up). For the vehicle it is
/// the centre of the rear axle, the point whose turning radius the Reeds-Shepp space models.
struct Pose2 {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

enum class Direction { kForward, kReverse };
const char* DirectionName(Direction direction);

/// One pose of the output path with the height of the ground it was projected onto.
struct PathPose {
  Pose2 pose;
  double z_m = 0.0;
};

/// A stretch of the path driven in one direction. Consecutive segments of a Path share the cusp
/// pose: the last pose of one is the first pose of the next.
struct PathSegment {
  Direction direction = Direction::kForward;
  std::vector<PathPose> poses;  ///< at least two
  /// Length of the polyline through the poses, m.
  double Length() const;
};

/// The planner's output: segments split at cusps (where the vehicle stops and changes direction).
/// Immutable once built: the segments and the flat pose list are set together by the constructor, so
/// Poses() is a reference to stored poses that stays valid as long as the Path does.
class Path {
 public:
  Path() = default;
  /// Consecutive segments share the cusp pose (the last pose of one is the first of the next).
  explicit Path(std::vector<PathSegment> segments);

  const std::vector<PathSegment>& segments() const { return segments_; }
  bool empty() const { return segments_.empty(); }
  double Length() const;
  /// Every pose once, in driving order (cusp poses are not repeated).
  const std::vector<PathPose>& Poses() const { return poses_; }
  int NumCusps() const { return segments_.empty() ? 0 : static_cast<int>(segments_.size()) - 1; }
  /// The poses `first` to `last` (indices into Poses(), inclusive) with their segments and cusps; an
  /// empty path when fewer than two poses remain.
  Path Slice(std::size_t first, std::size_t last) const;
  /// The same path with every pose moved by (dx, dy, dz) (a frame with the same axes).
  Path Shifted(double dx_m, double dy_m, double dz_m) const;

 private:
  std::vector<PathSegment> segments_;
  std::vector<PathPose> poses_;  ///< the segments' poses, cusps once
};

/// Horizontal distance from p to the polyline through the path's poses; +inf for an empty path.
double DistanceToPolyline(const Path& path, const Eigen::Vector2d& p);

}  // namespace ovpc::planner
