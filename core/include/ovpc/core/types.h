// Plain value types shared by every stage of the OVPC pipeline.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ovpc {

using Vec3 = Eigen::Vector3d;
/// A point cloud: positions only, in the frame named by the variable (`points_S`, `points_L`, ...).
using Points = std::vector<Vec3>;
/// A triangle as three vertex indices.
using Triangle = std::array<int, 3>;

inline constexpr double kPi = 3.14159265358979323846;
constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }

}  // namespace ovpc
