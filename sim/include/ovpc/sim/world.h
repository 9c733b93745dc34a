// The world description: terrain plus objects, as plain values. One description builds both the
// MuJoCo model (the vehicle drives on it) and the Embree scene (the LiDAR sees it), so physics and
// sensing agree. The scenario layer fills it from YAML.
#pragma once

#include <string>
#include <vector>

#include "ovpc/core/types.h"
#include "ovpc/sim/terrain.h"

namespace ovpc::sim {

// Object heights are measured from the terrain at the object's centre (x, y). An object whose
// base is at or below the ground (base_m <= 0) is extended down to the lowest terrain under its
// footprint, so posts and walls stand on slopes without a gap.

/// A box (wall, rock, roof slab), rotated about the vertical by yaw_deg.
struct BoxObject {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_deg = 0.0;
  double length_m = 1.0;  ///< along its x axis
  double width_m = 1.0;   ///< along its y axis
  double height_m = 1.0;
  double base_m = 0.0;    ///< bottom above the ground at the centre
};

/// A vertical cylinder (post, pole, trunk).
struct CylinderObject {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.1;
  double height_m = 2.0;
  double base_m = 0.0;
};

/// An ellipsoid (tree crown, bush; a sphere when the three radii are equal), rotated by yaw_deg.
struct EllipsoidObject {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_deg = 0.0;
  double centre_height_m = 1.0;  ///< centre above the ground
  double radius_x_m = 0.5;
  double radius_y_m = 0.5;
  double radius_z_m = 0.5;
};

/// A carport: a roof slab on four posts at its corners, rotated by yaw_deg.
struct CarportObject {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_deg = 0.0;
  double length_m = 6.0;
  double width_m = 4.0;
  double roof_height_m = 2.5;  ///< roof underside above the ground at the centre
  double roof_thickness_m = 0.1;
  double post_radius_m = 0.08;
  double post_inset_m = 0.1;  ///< post centres inside the roof's edges
};

struct World {
  TerrainConfig terrain;
  std::vector<BoxObject> boxes;
  std::vector<CylinderObject> cylinders;
  std::vector<EllipsoidObject> ellipsoids;
  std::vector<CarportObject> carports;

  /// @throws std::invalid_argument naming the offending object and field.
  void Validate() const;
};

/// An object in world coordinates: the common form MuJoCo and Embree are built from.
struct Solid {
  enum class Shape { kBox, kCylinder, kEllipsoid };
  Shape shape = Shape::kBox;
  Eigen::Isometry3d T_W_X = Eigen::Isometry3d::Identity();  ///< centre and axes
  /// Box: half extents; cylinder: (radius, radius, half height) about its z axis; ellipsoid: radii.
  Vec3 half_extents = Vec3::Ones();
  std::string name;  ///< "box3", "carport0_roof", ... (unique, for contacts and debugging)
};

/// Every object as a solid in W (carports expand to a roof box and four posts), in the order boxes,
/// cylinders, ellipsoids, carports.
/// @throws std::invalid_argument if the world is invalid.
std::vector<Solid> ResolveSolids(const World& world, const Heightfield& terrain);

}  // namespace ovpc::sim
