// Generated scenes for the planner's tests and benchmark: point clouds of ground, posts, roofs and
// slopes, run through the real OvpcMapper from a viewpoint 1.88 m above the vehicle (the paper's
// mast), and wrapped as a VertexCloudMap. The world frame has the ground at z = 0.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/planner/vertex_cloud_map.h"

namespace ovpc::testing {

inline constexpr double kSensorHeightM = 1.88;  ///< viewpoint above the vehicle (paper)

struct Rect {
  double min_x, max_x, min_y, max_y;
  bool Contains(double x, double y) const { return x >= min_x && x <= max_x && y >= min_y && y <= max_y; }
};

/// A vertical post as rings of points every 0.2 m up to `height`.
struct Post {
  double x, y, radius = 0.15, height = 1.0;
};

struct SceneSpec {
  Rect ground{-11.0, 11.0, -9.0, 9.0};
  double spacing_m = 0.25;
  /// Ground height: 0, except a ramp rising along +x at `slope_deg` from `ramp_start_x` to
  /// `ramp_end_x` over the whole width, and a plateau at the ramp's top beyond it.
  double slope_deg = 0.0;
  double ramp_start_x = 1e9, ramp_end_x = 1e9;
  std::vector<Post> posts;
  std::vector<std::pair<Rect, double>> roofs;  ///< roof rectangle and its height
  /// The vehicle that took the scan stands here; the viewpoint is kSensorHeightM above the ground.
  double viewpoint_x = -7.0, viewpoint_y = 0.0;
  /// GHPR kernel parameter. The paper's useful range is -0.01 .. -0.03 (-0.03 on the robot). These
  /// grids are dense right down to the vehicle, where a LiDAR leaves a blind zone, and the strong
  /// kernel then hides most ground more than a few metres behind any obstacle or under a roof; -0.01
  /// keeps what a straight line of sight reaches, so that goals behind obstacles stay in the map.
  double gamma = -0.01;
  planner::Pose2 start{-7.0, 0.0, 0.0};
  planner::Pose2 goal{7.0, 0.0, 0.0};

  double GroundHeight(double x) const {
    const double t = std::tan(slope_deg * 3.14159265358979323846 / 180.0);
    if (x <= ramp_start_x) return 0.0;
    return t * (std::min(x, ramp_end_x) - ramp_start_x);
  }

  Points MakeCloud() const {
    Points pts;
    for (double x = ground.min_x; x <= ground.max_x + 1e-9; x += spacing_m) {
      for (double y = ground.min_y; y <= ground.max_y + 1e-9; y += spacing_m) {
        bool inside_post = false;
        for (const Post& p : posts) inside_post |= std::hypot(x - p.x, y - p.y) < p.radius;
        if (!inside_post) pts.emplace_back(x, y, GroundHeight(x));
      }
    }
    for (const Post& p : posts) {
      const double base = GroundHeight(p.x);
      const int around = std::max(8, static_cast<int>(std::ceil(2.0 * 3.14159265358979323846 * p.radius / 0.08)));
      for (double z = 0.1; z <= p.height + 1e-9; z += 0.2) {
        for (int k = 0; k < around; ++k) {
          const double a = 2.0 * 3.14159265358979323846 * k / around;
          pts.emplace_back(p.x + p.radius * std::cos(a), p.y + p.radius * std::sin(a), base + z);
        }
      }
    }
    for (const auto& [r, height] : roofs) {
      for (double x = r.min_x; x <= r.max_x + 1e-9; x += spacing_m) {
        for (double y = r.min_y; y <= r.max_y + 1e-9; y += spacing_m) pts.emplace_back(x, y, height);
      }
    }
    return pts;
  }

  Vec3 Viewpoint() const {
    return Vec3(viewpoint_x, viewpoint_y, GroundHeight(viewpoint_x) + kSensorHeightM);
  }
};

/// A scene built into a planning map.
struct PlanningScene {
  SceneSpec spec;
  OvpcMap ovpc;
  std::shared_ptr<planner::VertexCloudMap> map;
};

inline PlanningScene BuildScene(const SceneSpec& spec) {
  PlanningScene scene;
  scene.spec = spec;
  const Vec3 viewpoint = spec.Viewpoint();
  OvpcMapper::Config mapper;
  mapper.ghpr.gamma = spec.gamma;
  scene.ovpc = OvpcMapper(mapper).Update(spec.MakeCloud(), viewpoint);
  planner::GroundContext ground;
  ground.ground_reference_z_m = viewpoint.z() - kSensorHeightM;
  scene.map = std::make_shared<planner::VertexCloudMap>(scene.ovpc.cloud, planner::VertexCloudMap::Config{}, ground);
  return scene;
}

// The scenes of the planner issue. GHPR leaves unknown whatever an obstacle hides from the viewpoint,
// and a goal straight behind an obstacle as seen from the start is hidden when the scan is taken at
// the start. Scenes whose obstacle stands across the line from start to goal are therefore scanned by
// a vehicle standing beside them, so that start, goal and the way around are all in view.

inline SceneSpec FlatScene() { return SceneSpec{}; }

/// The flat scene built once per test program (the mapper is the slow part).
inline const PlanningScene& FlatPlanningScene() {
  static const PlanningScene scene = BuildScene(FlatScene());
  return scene;
}
inline const planner::VertexCloudMap& FlatMap() { return *FlatPlanningScene().map; }

/// A 3 x 3 cluster of posts 1.2 m apart across the straight line: the gaps are narrower than the
/// vehicle. Scanned from the side.
inline SceneSpec PostsScene() {
  SceneSpec spec;
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) spec.posts.push_back(Post{1.2 * i, 1.2 * j});
  }
  spec.viewpoint_x = 0.0;
  spec.viewpoint_y = -7.0;
  return spec;
}

inline Rect CarportRoof() { return Rect{-2.0, 2.0, -3.0, 3.0}; }

/// A carport: a roof on four posts across the straight line, scanned from the start. The goal is
/// just past the roof: farther on, the roof hides the ground.
inline SceneSpec CarportScene(double roof_height_m = 2.5) {
  SceneSpec spec;
  const Rect roof = CarportRoof();
  spec.roofs.push_back({roof, roof_height_m});
  for (double x : {roof.min_x, roof.max_x}) {
    for (double y : {roof.min_y, roof.max_y}) spec.posts.push_back(Post{x, y, 0.1, roof_height_m});
  }
  spec.goal = planner::Pose2{4.0, 0.0, 0.0};
  return spec;
}

inline Rect LowRoof() { return Rect{-1.5, 1.5, -3.0, 3.0}; }

/// A slab at 1.6 m (below the 2.2 m mast) across the straight line, scanned from the side.
inline SceneSpec LowRoofScene() {
  SceneSpec spec;
  spec.roofs.push_back({LowRoof(), 1.6});
  spec.viewpoint_x = 0.0;
  spec.viewpoint_y = -7.0;
  return spec;
}

/// A ramp of `slope_deg` over the whole width from x = -1 to x = 1, a plateau beyond; the goal is
/// on the plateau.
inline SceneSpec SlopeScene(double slope_deg) {
  SceneSpec spec;
  spec.slope_deg = slope_deg;
  spec.ramp_start_x = -1.0;
  spec.ramp_end_x = 1.0;
  spec.goal = planner::Pose2{6.0, 0.0, 0.0};
  return spec;
}

}  // namespace ovpc::testing
