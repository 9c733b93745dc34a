// Analytic outdoor scenes and the simulated VLP-16 on its spinning base (see synthetic_scene.h).
//
// Scan model used by SimulateScans (the tests rely on it):
//  - scan k of a call covers [t0 + k / scan_hz, t0 + (k + 1) / scan_hz]; its `time_s` and `T_O_S`
//    are those of the scan's end;
//  - the scan has n = round(2 pi / azimuth_step_rad) firings; firing j has azimuth j * step and is
//    fired at t_start + j / (n * scan_hz); all 16 lasers of a firing share its time and sensor pose
//    (the 2.3 us between lasers of one firing cycle are ignored);
//  - each hit is taken in the sensor frame at its firing time and carried into the sensor frame at
//    the scan's end with the known poses (exact motion compensation);
//  - points are stored firing by firing, laser id 0..15 within a firing, misses skipped.
#include "ovpc/synth/synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace ovpc::synth {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Keeps the smaller of `best` and `t` when `t` is a positive distance.
void KeepNearest(double t, double* best) {
  if (t > 0.0 && t < *best) *best = t;
}

/// A half-space n . x <= c.
struct HalfSpace {
  Vec3 normal;
  double offset;
};

/// Nearest positive distance at which the ray meets the boundary of the convex intersection of
/// `half_spaces` (entry if the origin is outside, exit if inside), or +inf.
template <std::size_t N>
double RaycastConvex(const std::array<HalfSpace, N>& half_spaces, const Vec3& origin,
                     const Vec3& direction) {
  double t_near = -kInf;
  double t_far = kInf;
  for (const HalfSpace& h : half_spaces) {
    const double denom = h.normal.dot(direction);
    const double num = h.offset - h.normal.dot(origin);
    if (denom == 0.0) {
      if (num < 0.0) return kInf;  // parallel to the plane and outside it
      continue;
    }
    const double t = num / denom;
    if (denom < 0.0) {
      t_near = std::max(t_near, t);
    } else {
      t_far = std::min(t_far, t);
    }
    if (t_near > t_far) return kInf;
  }
  if (t_near > 0.0) return t_near;
  if (t_far > 0.0) return t_far;  // +inf when the region is unbounded along the ray
  return kInf;
}

double RaycastBox(const Box& box, const Vec3& origin, const Vec3& direction) {
  double t_near = -kInf;
  double t_far = kInf;
  for (int i = 0; i < 3; ++i) {
    if (direction[i] == 0.0) {
      if (origin[i] < box.min[i] || origin[i] > box.max[i]) return kInf;
      continue;
    }
    double t0 = (box.min[i] - origin[i]) / direction[i];
    double t1 = (box.max[i] - origin[i]) / direction[i];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
    if (t_near > t_far) return kInf;
  }
  if (t_near > 0.0) return t_near;
  if (t_far > 0.0) return t_far;
  return kInf;
}

/// Real roots of a t^2 + b t + c = 0 (a > 0) in ascending order; false when there are none.
bool SolveQuadratic(double a, double b, double c, double* t0, double* t1) {
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return false;
  // The form that avoids cancellation between -b and the root.
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  if (q == 0.0) {  // b == 0 and c == 0
    *t0 = *t1 = 0.0;
    return true;
  }
  *t0 = q / a;
  *t1 = c / q;
  if (*t0 > *t1) std::swap(*t0, *t1);
  return true;
}

double RaycastSphere(const Sphere& sphere, const Vec3& origin, const Vec3& direction) {
  const Vec3 oc = origin - sphere.centre;
  double t0 = 0.0;
  double t1 = 0.0;
  if (!SolveQuadratic(direction.squaredNorm(), 2.0 * oc.dot(direction),
                      oc.squaredNorm() - sphere.radius_m * sphere.radius_m, &t0, &t1)) {
    return kInf;
  }
  double best = kInf;
  KeepNearest(t0, &best);
  KeepNearest(t1, &best);
  return best;
}

double RaycastCylinder(const Cylinder& cyl, const Vec3& origin, const Vec3& direction) {
  const double z_bottom = cyl.base.z();
  const double z_top = cyl.base.z() + cyl.height_m;
  const double r2 = cyl.radius_m * cyl.radius_m;
  const double ox = origin.x() - cyl.base.x();
  const double oy = origin.y() - cyl.base.y();
  double best = kInf;
  // Lateral surface, within the height.
  const double a = direction.x() * direction.x() + direction.y() * direction.y();
  double t0 = 0.0;
  double t1 = 0.0;
  if (a > 0.0 && SolveQuadratic(a, 2.0 * (ox * direction.x() + oy * direction.y()),
                                ox * ox + oy * oy - r2, &t0, &t1)) {
    for (const double t : {t0, t1}) {
      const double z = origin.z() + t * direction.z();
      if (z >= z_bottom && z <= z_top) KeepNearest(t, &best);
    }
  }
  // Caps, within the radius.
  if (direction.z() != 0.0) {
    for (const double z_cap : {z_bottom, z_top}) {
      const double t = (z_cap - origin.z()) / direction.z();
      const double x = ox + t * direction.x();
      const double y = oy + t * direction.y();
      if (x * x + y * y <= r2) KeepNearest(t, &best);
    }
  }
  return best;
}

bool HasRamp(const Scene& scene) {
  return scene.ramp_half_width > 0.0 && scene.ramp_end_x > scene.ramp_start_x &&
         scene.ramp_slope_rad > 0.0 && scene.ramp_slope_rad < 0.5 * kPi;
}

/// The ground is the solid z <= GroundHeight(x, y): the half-space z <= 0 united with the ramp
/// block {z >= 0, z <= tan(slope) (x - start), z <= plateau height, |y - centre| <= half width},
/// which is convex. Its boundary includes the vertical side walls of the ramp and plateau.
double RaycastGround(const Scene& scene, const Vec3& origin, const Vec3& direction) {
  double best = kInf;
  if (direction.z() != 0.0) KeepNearest(-origin.z() / direction.z(), &best);
  if (HasRamp(scene)) {
    const double tan_slope = std::tan(scene.ramp_slope_rad);
    const double top_m = tan_slope * (scene.ramp_end_x - scene.ramp_start_x);
    const std::array<HalfSpace, 5> block = {{
        {Vec3(0.0, 0.0, -1.0), 0.0},
        {Vec3(-tan_slope, 0.0, 1.0), -tan_slope * scene.ramp_start_x},
        {Vec3(0.0, 0.0, 1.0), top_m},
        {Vec3(0.0, 1.0, 0.0), scene.ramp_centre_y + scene.ramp_half_width},
        {Vec3(0.0, -1.0, 0.0), -(scene.ramp_centre_y - scene.ramp_half_width)},
    }};
    KeepNearest(RaycastConvex(block, origin, direction), &best);
  }
  return best;
}

void CheckMount(const SpinningLidarMount& mount) {
  auto require = [](bool ok, const char* field) {
    if (!ok) throw std::invalid_argument(std::string("SpinningLidarMount::") + field + " invalid");
  };
  require(std::isfinite(mount.height_m), "height_m");
  require(std::isfinite(mount.tilt_rad), "tilt_rad");
  require(std::isfinite(mount.spin_hz), "spin_hz");
  require(mount.scan_hz > 0.0 && std::isfinite(mount.scan_hz), "scan_hz");
  require(mount.azimuth_step_rad > 0.0 && mount.azimuth_step_rad <= kPi, "azimuth_step_rad");
  require(mount.min_range_m >= 0.0 && mount.max_range_m > mount.min_range_m, "min/max_range_m");
}

// Layout of the outdoor scene (metres, degrees).
constexpr double kRampStartX_m = 6.0;
constexpr double kRampLength_m = 3.5;  // along x; plateau at 3.5 tan(20 deg) = 1.27 m
constexpr double kRampHalfWidth_m = 4.0;
constexpr double kRampSlopeDeg = 20.0;
constexpr double kCarportCentreX_m = -2.0;
constexpr double kCarportCentreY_m = 5.0;
constexpr double kCarportHalfX_m = 3.0;  // 6 m along x
constexpr double kCarportHalfY_m = 2.0;  // 4 m along y
constexpr double kRoofUnderside_m = 2.5;
constexpr double kRoofThickness_m = 0.1;
constexpr double kPostRadius_m = 0.08;
constexpr double kPostInset_m = 0.1;
constexpr double kVehicleClearance_m = 2.5;
constexpr double kObjectGap_m = 0.5;  // between placed objects, and from the ramp and carport
constexpr double kPlaceMinDist_m = 3.0;
constexpr double kPlaceMaxDist_m = 20.0;

/// A placed object's footprint in the xy plane.
struct Footprint {
  double x, y, radius_m;
};

bool OverlapsRampStrip(const Scene& scene, const Footprint& f) {
  const double margin = f.radius_m + kObjectGap_m;
  return f.x >= scene.ramp_start_x - margin &&
         std::abs(f.y - scene.ramp_centre_y) <= scene.ramp_half_width + margin;
}

bool OverlapsCarport(const Footprint& f) {
  const double margin = f.radius_m + kObjectGap_m;
  return std::abs(f.x - kCarportCentreX_m) <= kCarportHalfX_m + margin &&
         std::abs(f.y - kCarportCentreY_m) <= kCarportHalfY_m + margin;
}

}  // namespace

double Scene::GroundHeight(double x, double y) const {
  if (!HasRamp(*this) || x <= ramp_start_x || std::abs(y - ramp_centre_y) > ramp_half_width) {
    return 0.0;
  }
  return std::tan(ramp_slope_rad) * (std::min(x, ramp_end_x) - ramp_start_x);
}

double Scene::Raycast(const Vec3& origin, const Vec3& direction, double max_range_m) const {
  double best = RaycastGround(*this, origin, direction);
  for (const Cylinder& c : cylinders) best = std::min(best, RaycastCylinder(c, origin, direction));
  for (const Box& b : boxes) best = std::min(best, RaycastBox(b, origin, direction));
  for (const Sphere& s : spheres) best = std::min(best, RaycastSphere(s, origin, direction));
  return best <= max_range_m ? best : kInf;
}

Scene MakeOutdoorScene(std::uint64_t seed) {
  Scene scene;
  scene.ramp_start_x = kRampStartX_m;
  scene.ramp_end_x = kRampStartX_m + kRampLength_m;
  scene.ramp_centre_y = 0.0;
  scene.ramp_half_width = kRampHalfWidth_m;
  scene.ramp_slope_rad = DegToRad(kRampSlopeDeg);

  // Carport: a roof slab on four posts at its corners.
  const double roof_top_m = kRoofUnderside_m + kRoofThickness_m;
  scene.boxes.push_back(Box{
      Vec3(kCarportCentreX_m - kCarportHalfX_m, kCarportCentreY_m - kCarportHalfY_m,
           kRoofUnderside_m),
      Vec3(kCarportCentreX_m + kCarportHalfX_m, kCarportCentreY_m + kCarportHalfY_m,
           roof_top_m)});
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      const Vec3 base(kCarportCentreX_m + sx * (kCarportHalfX_m - kPostInset_m),
                      kCarportCentreY_m + sy * (kCarportHalfY_m - kPostInset_m), 0.0);
      scene.cylinders.push_back(Cylinder{base, kPostRadius_m, kRoofUnderside_m});
    }
  }

  // Poles and trees, placed by rejection sampling. The distributions are the standard library's,
  // so layouts are reproducible on one platform (not necessarily across standard libraries).
  std::mt19937_64 rng(seed);
  auto uniform = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  auto uniform_int = [&rng](int lo, int hi) {
    return std::uniform_int_distribution<int>(lo, hi)(rng);
  };
  std::vector<Footprint> placed;
  // Returns a free footprint centre for an object of the given xy radius, or false after too many
  // attempts (never happens for the counts used here, but keeps the loop bounded).
  auto place = [&](double radius_m, double* x, double* y) {
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const double dist_m = uniform(kPlaceMinDist_m, kPlaceMaxDist_m);
      const double angle_rad = uniform(-kPi, kPi);
      const Footprint f{dist_m * std::cos(angle_rad), dist_m * std::sin(angle_rad), radius_m};
      if (std::hypot(f.x, f.y) - radius_m < kVehicleClearance_m) continue;
      if (OverlapsRampStrip(scene, f) || OverlapsCarport(f)) continue;
      const bool clash = std::any_of(placed.begin(), placed.end(), [&f](const Footprint& o) {
        return std::hypot(f.x - o.x, f.y - o.y) < f.radius_m + o.radius_m + kObjectGap_m;
      });
      if (clash) continue;
      placed.push_back(f);
      *x = f.x;
      *y = f.y;
      return true;
    }
    return false;
  };

  const int num_poles = uniform_int(6, 10);
  for (int i = 0; i < num_poles; ++i) {
    const double radius_m = uniform(0.05, 0.15);
    const double height_m = uniform(1.0, 4.0);
    double x = 0.0;
    double y = 0.0;
    if (place(radius_m, &x, &y)) {
      scene.cylinders.push_back(Cylinder{Vec3(x, y, 0.0), radius_m, height_m});
    }
  }
  const int num_trees = uniform_int(5, 8);
  for (int i = 0; i < num_trees; ++i) {
    const double trunk_radius_m = uniform(0.1, 0.25);
    const double trunk_height_m = uniform(1.5, 3.0);
    const double crown_radius_m = uniform(1.0, 2.0);
    double x = 0.0;
    double y = 0.0;
    if (!place(crown_radius_m, &x, &y)) continue;
    scene.cylinders.push_back(Cylinder{Vec3(x, y, 0.0), trunk_radius_m, trunk_height_m});
    // The crown sits on the trunk, swallowing its top 40 % of a radius.
    scene.spheres.push_back(
        Sphere{Vec3(x, y, trunk_height_m + 0.6 * crown_radius_m), crown_radius_m});
  }
  return scene;
}

std::vector<Scan> SimulateScans(const Scene& scene, const SpinningLidarMount& mount,
                                const Eigen::Isometry3d& T_O_B, double t0_s, int num_scans,
                                double range_sigma_m, std::uint64_t seed) {
  CheckMount(mount);
  if (num_scans < 0) throw std::invalid_argument("SimulateScans: num_scans < 0");
  if (!(range_sigma_m >= 0.0) || !std::isfinite(range_sigma_m)) {
    throw std::invalid_argument("SimulateScans: range_sigma_m must be finite and >= 0");
  }
  const int num_firings = static_cast<int>(std::lround(2.0 * kPi / mount.azimuth_step_rad));
  const double scan_period_s = 1.0 / mount.scan_hz;
  const double firing_period_s = scan_period_s / num_firings;

  std::array<double, 16> cos_elevation{};
  std::array<double, 16> sin_elevation{};
  for (std::size_t i = 0; i < kVlp16ElevationDeg.size(); ++i) {
    cos_elevation[i] = std::cos(DegToRad(kVlp16ElevationDeg[i]));
    sin_elevation[i] = std::sin(DegToRad(kVlp16ElevationDeg[i]));
  }

  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise_m(0.0, 1.0);

  std::vector<Scan> scans;
  scans.reserve(static_cast<std::size_t>(num_scans));
  for (int k = 0; k < num_scans; ++k) {
    const double t_start_s = t0_s + k * scan_period_s;
    Scan scan;
    scan.time_s = t_start_s + scan_period_s;
    scan.T_O_S = T_O_B * mount.T_B_S(scan.time_s);
    const Eigen::Isometry3d T_Send_O = scan.T_O_S.inverse();
    scan.points_S.reserve(static_cast<std::size_t>(num_firings) * 16);
    for (int j = 0; j < num_firings; ++j) {
      const double t_s = t_start_s + j * firing_period_s;
      const double azimuth_rad = j * mount.azimuth_step_rad;
      const double cos_az = std::cos(azimuth_rad);
      const double sin_az = std::sin(azimuth_rad);
      const Eigen::Isometry3d T_O_Sj = T_O_B * mount.T_B_S(t_s);
      const Eigen::Isometry3d T_Send_Sj = T_Send_O * T_O_Sj;
      const Vec3 origin_O = T_O_Sj.translation();
      for (std::size_t laser = 0; laser < 16; ++laser) {
        const Vec3 dir_Sj(cos_elevation[laser] * cos_az, cos_elevation[laser] * sin_az,
                          sin_elevation[laser]);
        const double true_range_m =
            scene.Raycast(origin_O, T_O_Sj.linear() * dir_Sj, mount.max_range_m);
        if (!std::isfinite(true_range_m)) continue;
        const double range_m =
            range_sigma_m > 0.0 ? true_range_m + range_sigma_m * noise_m(rng) : true_range_m;
        if (range_m < mount.min_range_m || range_m > mount.max_range_m) continue;
        scan.points_S.push_back(T_Send_Sj * (range_m * dir_Sj));
      }
    }
    scans.push_back(std::move(scan));
  }
  return scans;
}

Points MakeOutdoorCloud(std::size_t num_points, std::uint64_t seed) {
  // A parked vehicle at the origin of O: the spinning base alone sweeps the tilted sensor around,
  // so 25 scans (1.25 s, 225 deg of base yaw) cover the surroundings without driving. Keeping the
  // vehicle static keeps the cloud exact and its viewpoint at a known height above flat ground.
  constexpr int kNumScans = 25;
  constexpr double kRangeSigma_m = 0.015;
  constexpr double kCropRadius_m = 25.0;
  // Voxel grids tried in turn until one leaves at least `num_points` points: the buffer's default
  // (0.1 m, >= 2 hits), finer grids, and last a 5 cm grid that keeps single hits. 25 scans give
  // about 190k hits, of which the 2-hit filter keeps about 20k-30k voxels, so a 50k cloud needs the
  // last step; the simulated noise is Gaussian without outliers, so dropping the hit test there
  // lets no outliers through.
  struct Grid {
    double voxel_size_m;
    int min_hits;
  };
  constexpr std::array<Grid, 5> kGrids = {{{0.1, 2}, {0.07, 2}, {0.05, 2}, {0.05, 1}, {0.03, 1}}};

  const Scene scene = MakeOutdoorScene(seed);
  const SpinningLidarMount mount;
  // The scene and the noise draw from separate streams of the same seed.
  std::vector<Scan> scans = SimulateScans(scene, mount, Eigen::Isometry3d::Identity(), 0.0,
                                          kNumScans, kRangeSigma_m, seed ^ 0x9e3779b97f4a7c15ULL);

  Points best;
  for (const Grid& grid : kGrids) {
    PointCloudBuffer::Config config;
    config.max_scans = kNumScans;
    config.crop_radius_m = kCropRadius_m;
    config.voxel_size_m = grid.voxel_size_m;
    config.min_hits = grid.min_hits;
    config.max_points = num_points;
    config.seed = seed;
    PointCloudBuffer buffer(config);
    for (const Scan& scan : scans) buffer.Push(scan);
    Points points_L = buffer.Build().points_L;
    if (points_L.size() > best.size()) best = std::move(points_L);
    if (best.size() >= num_points) break;
  }
  return best;
}

}  // namespace ovpc::synth
