#include "ovpc/planner/path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace ovpc::planner {

double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

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

Path::Path(std::vector<PathSegment> segments) : segments_(std::move(segments)) {
  for (std::size_t s = 0; s < segments_.size(); ++s) {
    const auto& poses = segments_[s].poses;
    poses_.insert(poses_.end(), poses.begin() + (s == 0 || poses.empty() ? 0 : 1), poses.end());
  }
}

double Path::Length() const {
  double length = 0.0;
  for (const PathSegment& s : segments_) length += s.Length();
  return length;
}

Path Path::Slice(std::size_t first, std::size_t last) const {
  std::vector<PathSegment> out;
  std::size_t index = 0;  // Poses() index of the segment's first pose
  for (std::size_t s = 0; s < segments_.size(); ++s) {
    const auto& poses = segments_[s].poses;
    // Segment s covers Poses() indices [begin, begin + size - 1]; after the first, its first pose is
    // the previous segment's last (the cusp).
    const std::size_t begin = s == 0 ? 0 : index - 1;
    PathSegment piece{segments_[s].direction, {}};
    for (std::size_t k = 0; k < poses.size(); ++k) {
      const std::size_t i = begin + k;
      if (i >= first && i <= last) piece.poses.push_back(poses[k]);
    }
    index = begin + poses.size();
    if (piece.poses.size() >= 2) out.push_back(std::move(piece));
  }
  return Path(std::move(out));
}

Path Path::Shifted(double dx_m, double dy_m, double dz_m) const {
  std::vector<PathSegment> out = segments_;
  for (PathSegment& segment : out) {
    for (PathPose& p : segment.poses) {
      p.pose.x_m += dx_m;
      p.pose.y_m += dy_m;
      p.z_m += dz_m;
    }
  }
  return Path(std::move(out));
}

double DistanceToPolyline(const Path& path, const Eigen::Vector2d& p) {
  const auto& poses = path.Poses();
  const auto xy = [&](std::size_t i) { return Eigen::Vector2d(poses[i].pose.x_m, poses[i].pose.y_m); };
  if (poses.size() == 1) return (xy(0) - p).norm();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < poses.size(); ++i) best = std::min(best, DistanceToSegment(p, xy(i), xy(i + 1)));
  return best;
}

}  // namespace ovpc::planner
