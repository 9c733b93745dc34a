// Simulator benchmark: LiDAR rays per second on one core, physics and physics + LiDAR cost per
// simulated second at the default terrain resolution, and render time per frame.
//
// World: the default 60 m x 60 m terrain at 0.2 m cells with fractal roughness (0.25 m amplitude;
// --rough 0 for flat ground),
// a carport, posts, trees (trunk + crown) and walls, placed by a fixed formula. The vehicle drives
// at 2 m/s on a gentle curve. Timing: both wall-clock (steady_clock) and the thread's CPU time
// (CLOCK_THREAD_CPUTIME_ID), because this machine is shared: the CPU figure is what one core
// costs, the wall figure what a run took. Everything runs on one thread (Embree builds with one).
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "ovpc/sim/renderer.h"
#include "ovpc/sim/simulator.h"

namespace ovpc::bench {
namespace {

using sim::Simulator;

struct Sample {
  double wall_s = 0.0;
  double cpu_s = 0.0;
};

struct Timer {
  std::chrono::steady_clock::time_point wall0 = std::chrono::steady_clock::now();
  double cpu0 = CpuSeconds();

  static double CpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  double WallS() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  }
  double CpuS() const { return CpuSeconds() - cpu0; }
};

struct Options {
  double seconds = 5.0;  // simulated seconds per physics case
  double cell_m = 0.2;
  double rough_m = 0.25;
  int frames = 20;
  int reps = 5;
  bool quick = false;
};

void PrintUsage(std::ostream& out) {
  out << "usage: ovpc_sim_bench [--seconds S] [--reps N] [--cell M] [--frames N] [--quick] [--help]\n"
         "  --seconds S  simulated seconds per physics case and repetition (default 5)\n"
         "  --reps N     repetitions of every case; best and median are reported (default 5)\n"
         "  --cell M     terrain cell size in metres (default 0.2, the simulator's default)\n"
         "  --rough A    terrain roughness amplitude in metres (default 0.25; 0 for flat)\n"
         "  --frames N   rendered frames (default 20)\n"
         "  --quick      smoke run: 1 simulated second, 1 repetition, 2 frames\n";
}

int ParseArgs(int argc, char** argv, Options* options) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](double* out) {
      if (i + 1 >= argc) return false;
      char* end = nullptr;
      *out = std::strtod(argv[++i], &end);
      return end != nullptr && *end == '\0' && std::isfinite(*out) && *out > 0.0;
    };
    double v = 0.0;
    if (arg == "--help" || arg == "-h") {
      PrintUsage(std::cout);
      return -1;
    } else if (arg == "--quick") {
      options->quick = true;
      options->seconds = 1.0;
      options->reps = 1;
      options->frames = 2;
    } else if (arg == "--seconds" && value(&v)) {
      options->seconds = v;
    } else if (arg == "--cell" && value(&v)) {
      options->cell_m = v;
    } else if (arg == "--rough" && i + 1 < argc) {
      options->rough_m = std::strtod(argv[++i], nullptr);
    } else if (arg == "--frames" && value(&v)) {
      options->frames = static_cast<int>(v);
    } else if (arg == "--reps" && value(&v)) {
      options->reps = static_cast<int>(v);
    } else {
      std::cerr << "ovpc_sim_bench: bad argument '" << arg << "'\n";
      PrintUsage(std::cerr);
      return 2;
    }
  }
  return 0;
}

sim::World BenchWorld(double cell_m, double rough_m) {
  sim::World world;
  world.terrain.kind = rough_m > 0.0 ? sim::TerrainConfig::Kind::kRough : sim::TerrainConfig::Kind::kFlat;
  world.terrain.cell_m = cell_m;
  world.terrain.rough.amplitude_m = std::max(0.0, rough_m);
  world.terrain.rough.seed = 3;
  sim::CarportObject carport;
  carport.x_m = 12.0;
  carport.y_m = 6.0;
  world.carports.push_back(carport);
  for (int i = 0; i < 8; ++i) {  // posts on a circle
    const double a = 2.0 * kPi * i / 8.0 + 0.3;
    sim::CylinderObject post;
    post.x_m = 9.0 * std::cos(a);
    post.y_m = 9.0 * std::sin(a);
    post.radius_m = 0.1;
    post.height_m = 2.5;
    world.cylinders.push_back(post);
  }
  for (int i = 0; i < 6; ++i) {  // trees further out
    const double a = 2.0 * kPi * i / 6.0;
    sim::CylinderObject trunk;
    trunk.x_m = 16.0 * std::cos(a);
    trunk.y_m = 16.0 * std::sin(a);
    trunk.radius_m = 0.2;
    trunk.height_m = 2.5;
    world.cylinders.push_back(trunk);
    sim::EllipsoidObject crown;
    crown.x_m = trunk.x_m;
    crown.y_m = trunk.y_m;
    crown.centre_height_m = 3.5;
    crown.radius_x_m = crown.radius_y_m = 1.6;
    crown.radius_z_m = 1.3;
    world.ellipsoids.push_back(crown);
  }
  for (int i = 0; i < 3; ++i) {  // walls
    sim::BoxObject wall;
    wall.x_m = -12.0 + 4.0 * i;
    wall.y_m = -12.0;
    wall.yaw_deg = 20.0 * i;
    wall.length_m = 4.0;
    wall.width_m = 0.3;
    wall.height_m = 2.0;
    world.boxes.push_back(wall);
  }
  return world;
}

Simulator::Config BenchConfig(const Options& options, bool lidar) {
  Simulator::Config config;
  config.world = BenchWorld(options.cell_m, options.rough_m);
  config.lidar_enabled = lidar;
  config.start_x_m = -8.0;
  return config;
}

/// Drives for `seconds` and returns the step loop's wall and CPU seconds.
Sample Drive(Simulator* simulator, double seconds) {
  simulator->SetCommand(0.08, 2.0);
  const Timer timer;
  simulator->StepFor(seconds);
  const Sample out{timer.WallS(), timer.CpuS()};
  simulator->TakeScans();
  return out;
}

/// Best and median of repeated measurements, each scaled by `scale` (e.g. to ms per unit).
void Report(const char* what, std::vector<Sample> samples, double scale, const char* unit,
            bool rate = false) {
  // For rates (per second) the best is the largest value; for costs the smallest.
  auto value = [&](double seconds) { return rate ? scale / seconds : scale * seconds; };
  std::sort(samples.begin(), samples.end(),
            [](const Sample& a, const Sample& b) { return a.cpu_s < b.cpu_s; });
  const Sample& best = samples.front();
  const Sample& median = samples[samples.size() / 2];
  std::printf("  %-48s %9.2f %9.2f %9.2f  %s\n", what, value(best.cpu_s), value(median.cpu_s),
              value(median.wall_s), unit);
}

int Main(int argc, char** argv) {
  Options options;
  const int parse = ParseArgs(argc, argv, &options);
  if (parse != 0) return parse < 0 ? 0 : parse;
  const int reps = std::max(1, options.reps);
  std::printf(
      "ovpc_sim_bench: terrain cell %.2f m, roughness %.2f m, %.1f simulated s per case, %d "
      "repetitions%s\n",
      options.cell_m, options.rough_m, options.seconds, reps, options.quick ? " (quick)" : "");
  std::printf("  %-48s %9s %9s %9s\n", "", "best cpu", "med cpu", "med wall");

  // World build: terrain, MuJoCo model, Embree scene.
  std::vector<Sample> build;
  std::unique_ptr<Simulator> with_lidar;
  for (int r = 0; r < reps; ++r) {
    const Timer timer;
    with_lidar = std::make_unique<Simulator>(BenchConfig(options, true));
    build.push_back({timer.WallS(), timer.CpuS()});
  }
  Report("build world (terrain, MuJoCo, Embree)", build, 1e3, "ms");
  std::printf("  %-48s %zu triangles, %d x %d heightfield\n", "",
              with_lidar->ray_caster().num_triangles(), with_lidar->terrain().num_rows(),
              with_lidar->terrain().num_cols());

  // LiDAR alone: a parked vehicle scanning the world (noise on, every ray cast and transformed).
  {
    std::vector<Sample> samples;
    std::size_t rays = 0;
    std::size_t returns = 0;
    for (int r = 0; r < reps; ++r) {
      sim::Vlp16Sim lidar(sim::Vlp16Sim::Config{}, &with_lidar->ray_caster());
      sim::TimedPose from{0.0, with_lidar->T_W_B()};
      std::vector<sim::TrueScan> scans;
      const Timer timer;
      const double step_s = 0.005;
      for (double t = 0.0; t < options.seconds - 1e-9; t += step_s) {
        const sim::TimedPose to{t + step_s, from.T_W_B};
        lidar.Advance(from, to, &scans);
        from = to;
      }
      samples.push_back({timer.WallS(), timer.CpuS()});
      rays = 0;
      returns = 0;
      for (const sim::TrueScan& s : scans) {
        rays += s.rays;
        returns += s.points_S.size();
      }
    }
    Report("VLP-16 rays per second, one core", samples, 1e-6 * static_cast<double>(rays),
           "M rays/s", true);
    std::printf("  %-48s %zu rays per repetition, %.0f %% returns\n", "", rays,
                100.0 * static_cast<double>(returns) / static_cast<double>(rays));
  }

  // Physics only, then physics + LiDAR, per simulated second.
  {
    std::vector<Sample> samples;
    Simulator physics(BenchConfig(options, false));
    physics.StepFor(0.5);  // settle
    for (int r = 0; r < reps; ++r) samples.push_back(Drive(&physics, options.seconds));
    Report("physics per simulated second", samples, 1e3 / options.seconds, "ms");
  }
  {
    std::vector<Sample> samples;
    with_lidar->StepFor(0.5);
    with_lidar->TakeScans();
    for (int r = 0; r < reps; ++r) samples.push_back(Drive(with_lidar.get(), options.seconds));
    Report("physics + LiDAR per simulated second", samples, 1e3 / options.seconds, "ms");
  }

  // Pictures: 640 x 480 frames, plain and with an overlay of a scan's points and a mesh.
  if (!sim::RendererAvailable()) {
    std::printf("  rendering: not built (no EGL/libpng)\n");
    return 0;
  }
  with_lidar->StepFor(0.05);
  sim::Overlay overlay;
  for (const Simulator::SensorScan& s : with_lidar->TakeScans()) {
    for (const Vec3& p : s.scan.points_S) {
      overlay.points.push_back({s.T_W_S * p, {1.0f, 0.3f, 0.2f, 1.0f}});
    }
  }
  // A 28,800-triangle mesh (a map's size) draped over the terrain ahead.
  const sim::Heightfield& terrain = with_lidar->terrain();
  const Vec3 centre = with_lidar->T_W_B().translation();
  const int n = 121;  // 120 x 120 quads, 0.1 m apart
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const double x = centre.x() - 2.0 + 0.1 * c;
      const double y = centre.y() - 6.0 + 0.1 * r;
      overlay.mesh_vertices_W.emplace_back(x, y, terrain.HeightAt(x, y) + 0.05);
    }
  }
  for (int r = 0; r + 1 < n; ++r) {
    for (int c = 0; c + 1 < n; ++c) {
      const int a = r * n + c;
      overlay.mesh_triangles.push_back({a, a + 1, a + n + 1});
      overlay.mesh_triangles.push_back({a, a + n + 1, a + n});
      const bool ok = (r + c) % 7 != 0;
      const sim::Rgba rgba =
          ok ? sim::Rgba{0.2f, 0.8f, 0.2f, 0.6f} : sim::Rgba{0.9f, 0.1f, 0.1f, 0.6f};
      overlay.mesh_face_rgba.push_back(rgba);
      overlay.mesh_face_rgba.push_back(rgba);
    }
  }
  try {
    const Timer init_timer;
    sim::Renderer renderer(*with_lidar);
    Report("renderer setup (EGL + MuJoCo context)", {{init_timer.WallS(), init_timer.CpuS()}}, 1e3,
           "ms");
    renderer.Render(sim::ChaseCamera{});  // warm-up
    // llvmpipe rasterises on its own threads: for frames the wall clock is the figure.
    std::vector<Sample> plain;
    std::vector<Sample> drawn;
    for (int i = 0; i < options.frames; ++i) {
      const Timer timer;
      renderer.Render(sim::ChaseCamera{});
      plain.push_back({timer.WallS(), timer.WallS()});
    }
    for (int i = 0; i < options.frames; ++i) {
      const Timer timer;
      renderer.Render(sim::ChaseCamera{}, overlay);
      drawn.push_back({timer.WallS(), timer.WallS()});
    }
    Report("render 640 x 480 frame (wall)", plain, 1e3, "ms");
    char label[96];
    std::snprintf(label, sizeof(label), "  + overlay, %zu points, %zu triangles (wall)",
                  overlay.points.size(), overlay.mesh_triangles.size());
    Report(label, drawn, 1e3, "ms");
    std::printf("  %-48s %s\n", "OpenGL renderer", renderer.gl_renderer().c_str());
  } catch (const std::exception& e) {
    std::printf("  rendering failed: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace
}  // namespace ovpc::bench

int main(int argc, char** argv) { return ovpc::bench::Main(argc, argv); }
