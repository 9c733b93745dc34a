#include "ovpc/planner/vertex_cloud_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace ovpc::planner {
namespace {

// A normal this close to horizontal cannot carry the vehicle; the box then stays upright.
constexpr double kMinNormalZ = 0.2;

}  // namespace

void VertexCloudMap::Config::Validate() const {
  if (!std::isfinite(ground_reference_z_m)) {
    throw std::invalid_argument("VertexCloudMap::Config: ground_reference_z_m must be finite");
  }
  if (!(max_projection_distance_m > 0.0) || !std::isfinite(max_projection_distance_m)) {
    throw std::invalid_argument("VertexCloudMap::Config: max_projection_distance_m must be > 0, got " +
                                std::to_string(max_projection_distance_m));
  }
}

VertexCloudMap::VertexCloudMap(TraversabilityCloud cloud, const Config& config)
    : cloud_(std::move(cloud)), config_(config) {
  config_.Validate();
  if (cloud_.empty()) return;  // empty bounds: every pose is outside the map
  bounds_.min_x_m = bounds_.min_y_m = std::numeric_limits<double>::infinity();
  bounds_.max_x_m = bounds_.max_y_m = -std::numeric_limits<double>::infinity();
  for (const Vec3& p : cloud_.points()) {
    bounds_.min_x_m = std::min(bounds_.min_x_m, p.x());
    bounds_.max_x_m = std::max(bounds_.max_x_m, p.x());
    bounds_.min_y_m = std::min(bounds_.min_y_m, p.y());
    bounds_.max_y_m = std::max(bounds_.max_y_m, p.y());
  }
}

std::optional<GroundPose> VertexCloudMap::Project(const Pose2& pose) const {
  // Nearest visible point to the pose at the reference height, then again at the height found: on a
  // slope the first answer lies uphill or downhill of the pose, the second is close below it.
  const auto first = cloud_.Nearest(Vec3(pose.x_m, pose.y_m, config_.ground_reference_z_m));
  if (!first) return std::nullopt;
  const Vec3 query(pose.x_m, pose.y_m, cloud_.points()[first->index].z());
  const auto nearest = cloud_.Nearest(query);
  if (!nearest || nearest->distance_m > config_.max_projection_distance_m) return std::nullopt;

  const Vec3& p = cloud_.points()[nearest->index];
  Vec3 normal = cloud_.normals()[nearest->index];
  GroundPose ground;
  ground.traversable = cloud_.traversable()[nearest->index] != 0;
  if (!(normal.z() >= kMinNormalZ)) {
    normal = Vec3::UnitZ();
    ground.traversable = false;
  }
  // Origin: the pose dropped vertically onto the tangent plane at the nearest point.
  const double z = p.z() - (normal.x() * (pose.x_m - p.x()) + normal.y() * (pose.y_m - p.y())) / normal.z();
  const Vec3 heading(std::cos(pose.yaw_rad), std::sin(pose.yaw_rad), 0.0);
  const Vec3 x_axis = (heading - heading.dot(normal) * normal).normalized();
  Eigen::Matrix3d R_L_B;
  R_L_B.col(0) = x_axis;
  R_L_B.col(1) = normal.cross(x_axis);
  R_L_B.col(2) = normal;
  ground.T_L_B.linear() = R_L_B;
  ground.T_L_B.translation() = Vec3(pose.x_m, pose.y_m, z);
  return ground;
}

bool VertexCloudMap::IsBoxFree(const GroundPose& ground, const VehicleBox& vehicle) const {
  // One oriented-box query covers the vehicle box and the slab under its footprint; each point found
  // is sorted by its height above the ground plane of the pose.
  const double half_length = 0.5 * vehicle.length_m + vehicle.margin_m;
  const double half_width = 0.5 * vehicle.width_m + vehicle.margin_m;
  const double top = vehicle.height_m + vehicle.margin_m;
  const double bottom = -vehicle.footprint_depth_m;
  Eigen::Isometry3d T_B_C = Eigen::Isometry3d::Identity();  // C: centre of the query box
  T_B_C.translation() = Vec3(vehicle.centre_ahead_m, 0.0, 0.5 * (top + bottom));
  const Eigen::Isometry3d T_L_C = ground.T_L_B * T_B_C;
  const std::vector<int> inside = cloud_.InBox(T_L_C, Vec3(half_length, half_width, 0.5 * (top - bottom)));
  if (inside.empty()) return true;
  const Eigen::Isometry3d T_B_L = ground.T_L_B.inverse();
  for (int i : inside) {
    const double height = (T_B_L * cloud_.points()[i]).z();
    if (height > vehicle.ground_clearance_m) return false;  // an obstacle, a roof, a wall in the box
    if (!cloud_.traversable()[i]) return false;              // non-traversable ground under the footprint
  }
  return true;
}

bool VertexCloudMap::IsKnownFree(double x_m, double y_m) const {
  if (!bounds_.Contains(x_m, y_m)) return false;
  const auto ground = Project(Pose2{x_m, y_m, 0.0});
  return ground && ground->traversable;
}

}  // namespace ovpc::planner
