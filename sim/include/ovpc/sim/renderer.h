// Headless pictures of the simulated world: MuJoCo's renderer on an EGL surfaceless context
// (Mesa's software rasteriser on a CPU-only machine; no display, no libGL), a chase camera behind
// the vehicle, and extra geometry drawn over the scene: the OVPC mesh coloured by traversability,
// points, the planned path.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "ovpc/core/free_space_mesh.h"
#include "ovpc/core/types.h"
#include "ovpc/sim/image.h"

namespace ovpc::sim {

class Simulator;

/// True when the library was built with EGL and libpng (else Renderer throws).
bool RendererAvailable();

using Rgba = std::array<float, 4>;

/// Geometry drawn over the scene, in world coordinates, unlit (faces shaded by their slope).
struct Overlay {
  struct Point {
    Vec3 position_W;
    Rgba rgba;
  };
  struct Polyline {
    std::vector<Vec3> vertices_W;
    Rgba rgba = {1.0f, 0.2f, 0.9f, 1.0f};
    float width_px = 3.0f;
  };
  std::vector<Point> points;
  float point_size_px = 3.0f;
  std::vector<Polyline> polylines;
  /// A triangle mesh with one colour per face (e.g. green traversable, red not).
  std::vector<Vec3> mesh_vertices_W;
  std::vector<Triangle> mesh_triangles;
  std::vector<Rgba> mesh_face_rgba;
  /// Hide overlay parts behind scene geometry (true), or draw them on top of everything.
  bool depth_test = true;

  /// Adds points given in frame X at pose T_W_X.
  void AddPoints(const Points& points_X, const Eigen::Isometry3d& T_W_X, const Rgba& rgba);
  /// Adds an OVPC free-space mesh given in its local frame L at pose T_W_L: traversable faces in
  /// `traversable_rgba`, the others in `blocked_rgba`; faces touching the viewpoint (the boundary
  /// of what was seen) are left out.
  void AddFreeSpaceMesh(const FreeSpaceMesh& mesh_L, const Eigen::Isometry3d& T_W_L,
                        const Rgba& traversable_rgba = {0.2f, 0.85f, 0.2f, 0.55f},
                        const Rgba& blocked_rgba = {0.9f, 0.15f, 0.1f, 0.55f});

  /// @throws std::invalid_argument if a face or colour index is inconsistent.
  void Validate() const;
};

/// A camera following the vehicle, looking along its heading from behind and above.
struct ChaseCamera {
  double distance_m = 10.0;       ///< from the look-at point
  double elevation_deg = -25.0;   ///< below the horizon
  double azimuth_offset_deg = 0.0;  ///< added to the vehicle's heading (180: from the front)
  double lookat_height_m = 1.0;   ///< look-at point above B
  double lookat_ahead_m = 2.0;    ///< look-at point ahead of B
};

class Renderer {
 public:
  /// Creates an EGL surfaceless context and MuJoCo's render context for the simulator's model.
  /// Pictures have the model's offscreen size (Simulator::Config::physics.offscreen_*). The
  /// simulator must outlive the renderer.
  /// @throws std::runtime_error with the failing step if EGL or OpenGL cannot be set up.
  explicit Renderer(const Simulator& sim);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Renders the simulator's current state from the chase camera, with the overlay on top.
  Image Render(const ChaseCamera& camera, const Overlay& overlay = Overlay{});

  /// "Mesa Intel..."/"llvmpipe ...": the OpenGL renderer string, for reports.
  std::string gl_renderer() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ovpc::sim
