// Foxglove's message schemas (https://docs.foxglove.dev/docs/visualization/message-schemas) in
// JSON encoding, as compact text: the schemas' JSON Schema for the MCAP Schema records and the
// writers of the messages the run log uses. Numbers are written with a fixed number of decimals
// (trailing zeros dropped), so that the same values always give the same bytes.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

namespace ovpc::scenarios::foxglove {

/// Simulated time in nanoseconds (the run log's clock; never the wall clock).
std::uint64_t Nanoseconds(double time_s);

/// The JSON Schema of a Foxglove schema by its name ("foxglove.PointCloud", ...) or of the
/// testbed's own "ovpc.Command"; empty for a name it does not know.
std::string JsonSchema(std::string_view name);

/// Appends JSON values to a message's text.
class Json {
 public:
  std::string& str() { return s_; }
  Json& Raw(std::string_view text) {
    s_ += text;
    return *this;
  }
  Json& Str(std::string_view text);                 ///< a quoted, escaped string
  Json& Num(double v, int decimals = 4);            ///< finite; non-finite values are written as 0
  Json& Int(std::int64_t v);
  Json& Time(std::uint64_t ns);                     ///< {"sec":..,"nsec":..}
  Json& Vec3(const Eigen::Vector3d& v, int decimals = 4);  ///< {"x":..,"y":..,"z":..}
  Json& Quat(const Eigen::Quaterniond& q);
  Json& Pose(const Eigen::Isometry3d& T);           ///< {"position":..,"orientation":..}
  Json& Color(float r, float g, float b, float a);

 private:
  std::string s_;
};

/// Base64 (RFC 4648, with padding) of `bytes`.
std::string Base64(std::string_view bytes);

/// A foxglove.FrameTransform message: `child` placed in `parent` by T_parent_child.
std::string FrameTransform(std::uint64_t ns, const std::string& parent, const std::string& child, const Eigen::Isometry3d& T);
/// A foxglove.PoseInFrame message.
std::string PoseInFrame(std::uint64_t ns, const std::string& frame, const Eigen::Isometry3d& T);
/// A foxglove.Log message (level: 2 info, 3 warning, 4 error).
std::string Log(std::uint64_t ns, int level, const std::string& name, const std::string& message);

/// A foxglove.PointCloud of float32 x, y, z (and, when `flags` is given, a uint8 field
/// `flag_name` per point), the points given in the cloud's own frame placed by `T_frame_cloud`.
std::string PointCloud(std::uint64_t ns, const std::string& frame, const Eigen::Isometry3d& T_frame_cloud,
                       const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint8_t>* flags = nullptr,
                       const std::string& flag_name = "");

/// One foxglove.SceneEntity of a SceneUpdate: its primitives are appended, already as JSON text
/// (comma-separated objects), by the caller.
struct Entity {
  std::string frame_id;
  std::string id;
  std::vector<std::pair<std::string, std::string>> metadata;
  std::string arrows, cubes, spheres, cylinders, lines, triangles;
};
/// A foxglove.SceneUpdate replacing the entities of the same id (no deletions).
std::string SceneUpdate(std::uint64_t ns, const std::vector<Entity>& entities);

}  // namespace ovpc::scenarios::foxglove
