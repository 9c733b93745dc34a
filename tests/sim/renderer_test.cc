#include "ovpc/sim/renderer.h"

#include <cstdio>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "ovpc/sim/image.h"
#include "ovpc/sim/simulator.h"

namespace ovpc::sim {
namespace {

/// Distinct colours, coarsely quantised.
std::size_t ColourCount(const Image& image) {
  std::set<int> colours;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
    colours.insert((image.rgb[i] >> 4) << 8 | (image.rgb[i + 1] >> 4) << 4 | (image.rgb[i + 2] >> 4));
  }
  return colours.size();
}

TEST(RendererTest, RendersTheChaseViewWithOverlayToPng) {
  if (!RendererAvailable()) GTEST_SKIP() << "built without EGL/libpng (see scripts/install-deps)";
  Simulator::Config config;
  config.world.terrain.size_x_m = 30.0;
  config.world.terrain.size_y_m = 30.0;
  config.lidar_enabled = false;
  CarportObject carport;
  carport.x_m = 6.0;
  config.world.carports.push_back(carport);
  Simulator sim(config);
  sim.StepFor(0.1);

  Renderer renderer(sim);
  const Image plain = renderer.Render(ChaseCamera{});
  EXPECT_EQ(plain.width, config.physics.offscreen_width);
  EXPECT_EQ(plain.height, config.physics.offscreen_height);
  ASSERT_EQ(plain.rgb.size(), 3u * plain.width * plain.height);
  EXPECT_GT(ColourCount(plain), 20u) << "blank picture (renderer " << renderer.gl_renderer() << ")";

  // A large magenta triangle ahead of the vehicle, drawn over everything.
  Overlay overlay;
  overlay.depth_test = false;
  overlay.mesh_vertices_W = {Vec3(3.0, -3.0, 0.1), Vec3(3.0, 3.0, 0.1), Vec3(8.0, 0.0, 0.1)};
  overlay.mesh_triangles = {{0, 1, 2}};
  overlay.mesh_face_rgba = {{1.0f, 0.0f, 1.0f, 1.0f}};
  overlay.points.push_back({Vec3(2.0, 0.0, 2.0), {0.0f, 1.0f, 1.0f, 1.0f}});
  overlay.polylines.push_back({{Vec3(0.0, 0.0, 0.2), Vec3(10.0, 0.0, 0.2)}, {0.0f, 0.0f, 1.0f, 1.0f}, 3.0f});
  const Image drawn = renderer.Render(ChaseCamera{}, overlay);
  std::size_t magenta = 0;
  for (std::size_t i = 0; i + 2 < drawn.rgb.size(); i += 3) {
    if (drawn.rgb[i] > 120 && drawn.rgb[i + 1] < 40 && drawn.rgb[i + 2] > 120) ++magenta;
  }
  EXPECT_GT(magenta, 2000u);
  EXPECT_NE(drawn.rgb, plain.rgb);

  const std::string path = ::testing::TempDir() + "ovpc_sim_render_test.png";
  WritePng(drawn, path);
  std::ifstream file(path, std::ios::binary);
  char signature[8] = {};
  file.read(signature, 8);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  std::remove(path.c_str());
}

TEST(OverlayTest, FreeSpaceMeshIsColouredByTraversabilityWithoutTheViewpointFaces) {
  FreeSpaceMesh mesh;
  mesh.vertices = {Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0), Vec3(1.0, 1.0, 0.0), Vec3::Zero()};
  mesh.viewpoint_vertex = 3;
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 0, 2}};
  mesh.face_traversable = {1, 0, 0};
  Eigen::Isometry3d T_W_L = Eigen::Isometry3d::Identity();
  T_W_L.translation() = Vec3(10.0, 0.0, 2.0);
  Overlay overlay;
  overlay.AddPoints({Vec3(1.0, 2.0, 3.0)}, T_W_L, {1.0f, 1.0f, 1.0f, 1.0f});
  overlay.AddFreeSpaceMesh(mesh, T_W_L);
  overlay.Validate();
  ASSERT_EQ(overlay.mesh_triangles.size(), 2u);  // the face on the viewpoint is left out
  EXPECT_EQ(overlay.mesh_face_rgba[0][1], 0.85f);  // traversable: green
  EXPECT_EQ(overlay.mesh_face_rgba[1][0], 0.9f);   // blocked: red
  EXPECT_EQ(overlay.mesh_vertices_W[2], Vec3(11.0, 1.0, 2.0));
  EXPECT_EQ(overlay.points[0].position_W, Vec3(11.0, 2.0, 5.0));
  overlay.mesh_face_rgba.pop_back();
  EXPECT_THROW(overlay.Validate(), std::invalid_argument);
}

TEST(RendererTest, WritePngRejectsInconsistentImages) {
  if (!RendererAvailable()) GTEST_SKIP() << "built without EGL/libpng (see scripts/install-deps)";
  Image image;
  image.width = 4;
  image.height = 4;
  image.rgb.resize(10);
  EXPECT_THROW(WritePng(image, ::testing::TempDir() + "bad.png"), std::invalid_argument);
}

}  // namespace
}  // namespace ovpc::sim
