#include "ovpc/planner/path.h"

#include <cmath>

namespace ovpc::planner {

double NormalizeYaw(double yaw_rad) {
  double yaw = std::remainder(yaw_rad, 2.0 * kPi);  // [-pi, pi]
  if (yaw >= kPi) yaw -= 2.0 * kPi;
  if (yaw < -kPi) yaw = -kPi;  // guards the rounding of values just below -pi
  return yaw;
}

const char* DirectionName(Direction direction) {
  return direction == Direction::kForward ? "forward" : "reverse";
}

double PathSegment::Length() const {
  double length = 0.0;
  for (std::size_t i = 1; i < poses.size(); ++i) {
    length += std::hypot(poses[i].pose.x_m - poses[i - 1].pose.x_m, poses[i].pose.y_m - poses[i - 1].pose.y_m);
  }
  return length;
}

double Path::Length() const {
  double length = 0.0;
  for (const PathSegment& s : segments) length += s.Length();
  return length;
}

std::vector<PathPose> Path::Poses() const {
  std::vector<PathPose> out;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const auto& poses = segments[s].poses;
    out.insert(out.end(), poses.begin() + (s == 0 || poses.empty() ? 0 : 1), poses.end());
  }
  return out;
}

Path Path::Slice(std::size_t first, std::size_t last) const {
  Path out;
  std::size_t index = 0;  // Poses() index of the segment's first pose
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const auto& poses = segments[s].poses;
    // Segment s covers Poses() indices [begin, begin + size - 1]; after the first, its first pose is
    // the previous segment's last (the cusp).
    const std::size_t begin = s == 0 ? 0 : index - 1;
    PathSegment piece{segments[s].direction, {}};
    for (std::size_t k = 0; k < poses.size(); ++k) {
      const std::size_t i = begin + k;
      if (i >= first && i <= last) piece.poses.push_back(poses[k]);
    }
    index = begin + poses.size();
    if (piece.poses.size() >= 2) out.segments.push_back(std::move(piece));
  }
  return out;
}

}  // namespace ovpc::planner
