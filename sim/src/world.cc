#include "ovpc/sim/world.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ovpc::sim {
namespace {

class Checker {
 public:
  explicit Checker(std::string object) : object_(std::move(object)) {}
  void Finite(double value, const char* field) const {
    if (!std::isfinite(value)) Fail(field, "must be finite");
  }
  void Positive(double value, const char* field) const {
    if (!(value > 0.0) || !std::isfinite(value)) Fail(field, "must be > 0");
  }
  [[noreturn]] void Fail(const char* field, const std::string& what) const {
    throw std::invalid_argument("World: " + object_ + "." + field + " " + what);
  }

 private:
  std::string object_;
};

/// A solid standing upright at (x, y) between the heights bottom_z and top_z (world z).
Solid Upright(Solid::Shape shape, double x_m, double y_m, double yaw_rad, double half_x_m,
              double half_y_m, double bottom_z_m, double top_z_m, std::string name) {
  Solid solid;
  solid.shape = shape;
  solid.T_W_X.translation() = Vec3(x_m, y_m, 0.5 * (bottom_z_m + top_z_m));
  solid.T_W_X.linear() = Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  solid.half_extents = Vec3(half_x_m, half_y_m, 0.5 * (top_z_m - bottom_z_m));
  solid.name = std::move(name);
  return solid;
}

/// Half extents along x and y of the axis-aligned box around a rectangle rotated by yaw.
Eigen::Vector2d RotatedHalfExtents(double half_x_m, double half_y_m, double yaw_rad) {
  const double c = std::abs(std::cos(yaw_rad));
  const double s = std::abs(std::sin(yaw_rad));
  return Eigen::Vector2d(c * half_x_m + s * half_y_m, s * half_x_m + c * half_y_m);
}

/// The bottom height of an object based at `base_m` above the ground at its centre; objects at or
/// below the ground reach down to the lowest terrain under their footprint.
double BottomZ(const Heightfield& terrain, double x_m, double y_m, const Eigen::Vector2d& half_xy,
               double base_m) {
  const double bottom_m = terrain.HeightAt(x_m, y_m) + base_m;
  if (base_m > 0.0) return bottom_m;
  return std::min(bottom_m, terrain.MinHeightIn(x_m - half_xy.x(), y_m - half_xy.y(),
                                                x_m + half_xy.x(), y_m + half_xy.y()));
}

}  // namespace

void World::Validate() const {
  terrain.Validate();
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const BoxObject& b = boxes[i];
    const Checker check("boxes[" + std::to_string(i) + "]");
    check.Finite(b.x_m, "x_m");
    check.Finite(b.y_m, "y_m");
    check.Finite(b.yaw_deg, "yaw_deg");
    check.Finite(b.base_m, "base_m");
    check.Positive(b.length_m, "length_m");
    check.Positive(b.width_m, "width_m");
    check.Positive(b.height_m, "height_m");
  }
  for (std::size_t i = 0; i < cylinders.size(); ++i) {
    const CylinderObject& c = cylinders[i];
    const Checker check("cylinders[" + std::to_string(i) + "]");
    check.Finite(c.x_m, "x_m");
    check.Finite(c.y_m, "y_m");
    check.Finite(c.base_m, "base_m");
    check.Positive(c.radius_m, "radius_m");
    check.Positive(c.height_m, "height_m");
  }
  for (std::size_t i = 0; i < ellipsoids.size(); ++i) {
    const EllipsoidObject& e = ellipsoids[i];
    const Checker check("ellipsoids[" + std::to_string(i) + "]");
    check.Finite(e.x_m, "x_m");
    check.Finite(e.y_m, "y_m");
    check.Finite(e.yaw_deg, "yaw_deg");
    check.Finite(e.centre_height_m, "centre_height_m");
    check.Positive(e.radius_x_m, "radius_x_m");
    check.Positive(e.radius_y_m, "radius_y_m");
    check.Positive(e.radius_z_m, "radius_z_m");
  }
  for (std::size_t i = 0; i < carports.size(); ++i) {
    const CarportObject& c = carports[i];
    const Checker check("carports[" + std::to_string(i) + "]");
    check.Finite(c.x_m, "x_m");
    check.Finite(c.y_m, "y_m");
    check.Finite(c.yaw_deg, "yaw_deg");
    check.Positive(c.length_m, "length_m");
    check.Positive(c.width_m, "width_m");
    check.Positive(c.roof_height_m, "roof_height_m");
    check.Positive(c.roof_thickness_m, "roof_thickness_m");
    check.Positive(c.post_radius_m, "post_radius_m");
    check.Finite(c.post_inset_m, "post_inset_m");
    if (c.post_inset_m < c.post_radius_m - 1e-12 ||
        2.0 * c.post_inset_m >= std::min(c.length_m, c.width_m)) {
      check.Fail("post_inset_m", "must be >= post_radius_m and < half the roof's length and width");
    }
  }
}

std::vector<Solid> ResolveSolids(const World& world, const Heightfield& terrain) {
  world.Validate();
  std::vector<Solid> solids;
  for (std::size_t i = 0; i < world.boxes.size(); ++i) {
    const BoxObject& b = world.boxes[i];
    const double yaw_rad = DegToRad(b.yaw_deg);
    const Eigen::Vector2d half_xy = RotatedHalfExtents(0.5 * b.length_m, 0.5 * b.width_m, yaw_rad);
    const double top_z_m = terrain.HeightAt(b.x_m, b.y_m) + b.base_m + b.height_m;
    const double bottom_z_m = BottomZ(terrain, b.x_m, b.y_m, half_xy, b.base_m);
    solids.push_back(Upright(Solid::Shape::kBox, b.x_m, b.y_m, yaw_rad, 0.5 * b.length_m,
                             0.5 * b.width_m, bottom_z_m, top_z_m, "box" + std::to_string(i)));
  }
  for (std::size_t i = 0; i < world.cylinders.size(); ++i) {
    const CylinderObject& c = world.cylinders[i];
    const Eigen::Vector2d half_xy(c.radius_m, c.radius_m);
    const double top_z_m = terrain.HeightAt(c.x_m, c.y_m) + c.base_m + c.height_m;
    const double bottom_z_m = BottomZ(terrain, c.x_m, c.y_m, half_xy, c.base_m);
    solids.push_back(Upright(Solid::Shape::kCylinder, c.x_m, c.y_m, 0.0, c.radius_m, c.radius_m,
                             bottom_z_m, top_z_m, "cylinder" + std::to_string(i)));
  }
  for (std::size_t i = 0; i < world.ellipsoids.size(); ++i) {
    const EllipsoidObject& e = world.ellipsoids[i];
    Solid solid;
    solid.shape = Solid::Shape::kEllipsoid;
    solid.T_W_X.translation() =
        Vec3(e.x_m, e.y_m, terrain.HeightAt(e.x_m, e.y_m) + e.centre_height_m);
    solid.T_W_X.linear() =
        Eigen::AngleAxisd(DegToRad(e.yaw_deg), Vec3::UnitZ()).toRotationMatrix();
    solid.half_extents = Vec3(e.radius_x_m, e.radius_y_m, e.radius_z_m);
    solid.name = "ellipsoid" + std::to_string(i);
    solids.push_back(solid);
  }
  for (std::size_t i = 0; i < world.carports.size(); ++i) {
    const CarportObject& c = world.carports[i];
    const std::string name = "carport" + std::to_string(i);
    const double yaw_rad = DegToRad(c.yaw_deg);
    const double underside_z_m = terrain.HeightAt(c.x_m, c.y_m) + c.roof_height_m;
    solids.push_back(Upright(Solid::Shape::kBox, c.x_m, c.y_m, yaw_rad, 0.5 * c.length_m,
                             0.5 * c.width_m, underside_z_m, underside_z_m + c.roof_thickness_m,
                             name + "_roof"));
    const Eigen::Rotation2Dd R(yaw_rad);
    int post = 0;
    for (const double sx : {-1.0, 1.0}) {
      for (const double sy : {-1.0, 1.0}) {
        const Eigen::Vector2d offset = R * Eigen::Vector2d(sx * (0.5 * c.length_m - c.post_inset_m),
                                                           sy * (0.5 * c.width_m - c.post_inset_m));
        const double x_m = c.x_m + offset.x();
        const double y_m = c.y_m + offset.y();
        const Eigen::Vector2d half_xy(c.post_radius_m, c.post_radius_m);
        const double bottom_z_m = BottomZ(terrain, x_m, y_m, half_xy, 0.0);
        if (bottom_z_m >= underside_z_m) {
          throw std::invalid_argument("World: carports[" + std::to_string(i) +
                                      "] has a post whose ground is above the roof");
        }
        solids.push_back(Upright(Solid::Shape::kCylinder, x_m, y_m, 0.0, c.post_radius_m,
                                 c.post_radius_m, bottom_z_m, underside_z_m,
                                 name + "_post" + std::to_string(post++)));
      }
    }
  }
  return solids;
}

}  // namespace ovpc::sim
