#include "ovpc/bench/normals_experiment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "ovpc/bench/report.h"
#include "ovpc/core/internal/hash.h"
#include "ovpc/core/point_cloud_buffer.h"

namespace ovpc::bench {
namespace {

void Require(bool ok, const char* field, const char* what) {
  if (!ok) {
    throw std::invalid_argument(std::string("SlopeSceneConfig::") + field + " " + what);
  }
}

/// Grid samples per axis that fit into [0, length] with step `spacing` (a tolerance of 1e-9 of a
/// step keeps the last one when length is a multiple of the step).
int StepsIn(double length, double spacing) {
  return static_cast<int>(std::floor(length / spacing + 1e-9)) + 1;
}

}  // namespace

void SlopeSceneConfig::Validate() const {
  Require(half_extent_m > 0.0 && std::isfinite(half_extent_m), "half_extent_m",
          "must be finite and > 0");
  Require(slope_start_x_m > -half_extent_m && slope_start_x_m < half_extent_m, "slope_start_x_m",
          "must lie inside the scene");
  Require(spacing_m > 0.0 && spacing_m <= half_extent_m, "spacing_m",
          "must be > 0 and at most half_extent_m");
  Require(2.0 * half_extent_m / spacing_m <= 1e5, "spacing_m", "gives more than 1e5 rows");
  Require(noise_m >= 0.0 && std::isfinite(noise_m), "noise_m", "must be finite and >= 0");
  Require(num_clouds >= 1 && num_clouds <= 1000, "num_clouds", "must be in [1, 1000]");
  Require(pose_error_deg >= 0.0 && pose_error_deg < 90.0, "pose_error_deg",
          "must be in [0, 90)");
  Require(pose_error_m >= 0.0 && std::isfinite(pose_error_m), "pose_error_m",
          "must be finite and >= 0");
  Require(viewpoint_height_m > 0.0 && std::isfinite(viewpoint_height_m), "viewpoint_height_m",
          "must be finite and > 0");
}

Vec3 SlopeNormal(double alpha_rad) {
  return Vec3(-std::sin(alpha_rad), 0.0, std::cos(alpha_rad));
}

void SampleSurfaces(double alpha_rad, const SlopeSceneConfig& config, Points* points,
                    std::vector<Surface>* surface) {
  points->clear();
  surface->clear();
  const double h = config.half_extent_m;
  const double s = config.spacing_m;
  const int num_y = StepsIn(2.0 * h, s);
  // Ground rows strictly before the slope's foot, which belongs to the slope.
  const int num_ground_x =
      static_cast<int>(std::ceil((config.slope_start_x_m + h) / s - 1e-9));
  // Slope rows along the surface, up to the scene's edge in x.
  const double slope_length_m = (h - config.slope_start_x_m) / std::cos(alpha_rad);
  const int num_slope_u = StepsIn(slope_length_m, s);
  points->reserve(static_cast<std::size_t>(num_y) * (num_ground_x + num_slope_u));
  surface->reserve(points->capacity());
  for (int i = 0; i < num_ground_x; ++i) {
    for (int j = 0; j < num_y; ++j) {
      points->emplace_back(-h + i * s, -h + j * s, 0.0);
      surface->push_back(Surface::kGround);
    }
  }
  const double cos_a = std::cos(alpha_rad);
  const double sin_a = std::sin(alpha_rad);
  for (int i = 0; i < num_slope_u; ++i) {
    const double u = i * s;
    for (int j = 0; j < num_y; ++j) {
      points->emplace_back(config.slope_start_x_m + u * cos_a, -h + j * s, u * sin_a);
      surface->push_back(Surface::kSlope);
    }
  }
}

SlopeScene MakeSlopeScene(double alpha_rad, const SlopeSceneConfig& config, std::uint64_t seed) {
  config.Validate();
  if (!(alpha_rad >= 0.0 && alpha_rad < DegToRad(90.0))) {
    throw std::invalid_argument("MakeSlopeScene: alpha must be in [0, 90) degrees");
  }
  SlopeScene scene;
  scene.alpha_rad = alpha_rad;
  scene.viewpoint = Vec3(0.0, 0.0, config.viewpoint_height_m);
  scene.ground_normal = Vec3::UnitZ();
  scene.slope_normal = SlopeNormal(alpha_rad);

  Points samples;
  std::vector<Surface> labels;
  SampleSurfaces(alpha_rad, config, &samples, &labels);

  std::mt19937_64 rng(seed);
  auto uniform = [&rng](double half_width) {
    return half_width > 0.0 ? std::uniform_real_distribution<double>(-half_width, half_width)(rng)
                            : 0.0;
  };
  const double angle_rad = DegToRad(config.pose_error_deg);
  scene.points.reserve(samples.size() * static_cast<std::size_t>(config.num_clouds));
  scene.surface.reserve(scene.points.capacity());
  for (int k = 0; k < config.num_clouds; ++k) {
    // The pose error of cloud k: roll, pitch, yaw, then the translation.
    const double roll = uniform(angle_rad);
    const double pitch = uniform(angle_rad);
    const double yaw = uniform(angle_rad);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) *
                               Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
                               Eigen::AngleAxisd(roll, Vec3::UnitX()))
                                  .toRotationMatrix();
    const Vec3 t(uniform(config.pose_error_m), uniform(config.pose_error_m),
                 uniform(config.pose_error_m));
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const Vec3 noisy = samples[i] + Vec3(uniform(config.noise_m), uniform(config.noise_m),
                                           uniform(config.noise_m));
      scene.points.push_back(scene.viewpoint + R * (noisy - scene.viewpoint) + t);
      scene.surface.push_back(labels[i]);
    }
  }
  return scene;
}

double AngularErrorDeg(const Vec3& estimate, const Vec3& truth) {
  if (!estimate.allFinite() || estimate.isZero(0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  // atan2 of the sine and cosine parts stays accurate for angles near 0 and 180 degrees.
  return RadToDeg(std::atan2(estimate.cross(truth).norm(), estimate.dot(truth)));
}

double UnorientedDeg(double oriented_error_deg) {
  return std::min(oriented_error_deg, 180.0 - oriented_error_deg);
}

std::vector<double> MethodErrors::Degrees() const {
  std::vector<double> out;
  out.reserve(errors.size());
  for (const PointError& e : errors) out.push_back(e.error_deg);
  return out;
}

MethodErrors OvpcErrors(const SlopeScene& scene, const OvpcMap& map) {
  MethodErrors out;
  if (!map.ok()) return out;
  if (map.input.used != scene.points.size()) {
    throw std::logic_error("OvpcErrors: the mapper dropped points; indices would not match");
  }
  const std::vector<Vec3>& normals = map.cloud.normals();
  out.errors.reserve(normals.size());
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const int source = map.mesh.source_index[v];
    if (source < 0) continue;  // the viewpoint, never a visible point of the cloud
    const auto i = static_cast<std::size_t>(source);
    const double error = AngularErrorDeg(normals[v], scene.TrueNormal(i));
    if (std::isnan(error)) {
      ++out.without_normal;
    } else {
      out.errors.push_back({i, error, scene.points[i], scene.surface[i]});
    }
  }
  return out;
}

Surface SurfaceAt(const Vec3& position, const SlopeSceneConfig& config) {
  return position.x() < config.slope_start_x_m ? Surface::kGround : Surface::kSlope;
}

MethodErrors OvpcErrorsByPosition(const SlopeScene& scene, const SlopeSceneConfig& config,
                                  const OvpcMap& map) {
  MethodErrors out;
  if (!map.ok()) return out;
  const Points& points = map.cloud.points();
  const std::vector<Vec3>& normals = map.cloud.normals();
  out.errors.reserve(normals.size());
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const Surface surface = SurfaceAt(points[v], config);
    const Vec3& truth = surface == Surface::kGround ? scene.ground_normal : scene.slope_normal;
    const double error = AngularErrorDeg(normals[v], truth);
    if (std::isnan(error)) {
      ++out.without_normal;
    } else {
      out.errors.push_back({v, error, points[v], surface});
    }
  }
  return out;
}

MethodErrors PointNormalErrors(const SlopeScene& scene, const baselines::PcaNormals& normals) {
  if (normals.normals.size() != scene.points.size()) {
    throw std::invalid_argument("PointNormalErrors: one normal per point expected");
  }
  MethodErrors out;
  out.errors.reserve(scene.points.size());
  for (std::size_t i = 0; i < scene.points.size(); ++i) {
    const double error = AngularErrorDeg(normals.normals[i], scene.TrueNormal(i));
    if (std::isnan(error)) {
      ++out.without_normal;
    } else {
      out.errors.push_back({i, error, scene.points[i], scene.surface[i]});
    }
  }
  return out;
}

NormalsTrial RunNormalsTrial(double alpha_deg, const SlopeSceneConfig& scene_config,
                             const OvpcMapper& mapper, const NormalEstimator& pca,
                             std::uint64_t seed, const OvpcInputFilter& filter,
                             const VertexNormals::Config* other_normals) {
  NormalsTrial trial;
  trial.alpha_deg = alpha_deg;
  trial.seed = seed;
  const SlopeScene scene = MakeSlopeScene(DegToRad(alpha_deg), scene_config, seed);
  trial.points = scene.points.size();
  const bool filtered = filter.voxel_size_m > 0.0;

  Clock::time_point start = Clock::now();
  const Points ovpc_input =
      filtered ? VoxelFilter(scene.points, filter.voxel_size_m, filter.min_hits) : Points{};
  const OvpcMap map = mapper.Update(filtered ? ovpc_input : scene.points, scene.viewpoint);
  const double ovpc_ms = MsSince(start, Clock::now());
  trial.ovpc_input_points = filtered ? ovpc_input.size() : scene.points.size();
  trial.ovpc_status = map.status;
  trial.ovpc = filtered ? OvpcErrorsByPosition(scene, scene_config, map) : OvpcErrors(scene, map);
  trial.ovpc.ms = ovpc_ms;
  if (other_normals != nullptr && map.ok()) {
    OvpcMap other = map;
    start = Clock::now();
    other.cloud = BuildTraversabilityCloud(other.mesh, *other_normals);
    const double other_ms = MsSince(start, Clock::now());
    trial.ovpc_other = filtered ? OvpcErrorsByPosition(scene, scene_config, other) : OvpcErrors(scene, other);
    trial.ovpc_other.ms = other_ms;
  }

  start = Clock::now();
  const baselines::PcaNormals normals = pca(scene.points, scene.viewpoint);
  const double pca_ms = MsSince(start, Clock::now());
  trial.pca = PointNormalErrors(scene, normals);
  trial.pca.ms = pca_ms;

  if (filtered) return trial;
  // PCA restricted to the points OVPC evaluated (visible, with a vertex normal or without).
  std::vector<std::uint8_t> visible(scene.points.size(), 0);
  for (const int source : map.mesh.source_index) {
    if (source >= 0) visible[static_cast<std::size_t>(source)] = 1;
  }
  for (const PointError& e : trial.pca.errors) {
    if (visible[e.index]) trial.pca_visible.errors.push_back(e);
  }
  for (std::size_t i = 0; i < scene.points.size(); ++i) {
    if (visible[i] && normals.normals[i].isZero(0.0)) ++trial.pca_visible.without_normal;
  }
  return trial;
}

namespace {

// Collects the names of the one choice in VertexNormals::Config.
struct RuleNames {
  std::map<std::string, VertexNormals::Rule> by_name;
  template <class T>
  void Field(const char*, T&, const char*, const char*) {}
  template <class E>
  void Choice(const char*, E&, Choices<E> choices, const char*) {
    for (const auto& [name, value] : choices) by_name[name] = value;
  }
  template <class C>
  void Section(const char*, C&, const char*) {}
};

}  // namespace

std::map<std::string, VertexNormals::Rule> VertexNormalRules() {
  VertexNormals::Config config;
  RuleNames names;
  VisitFields(config, names);
  return names.by_name;
}

std::string VertexNormalRuleName(VertexNormals::Rule rule) {
  for (const auto& [name, value] : VertexNormalRules()) {
    if (value == rule) return name;
  }
  return "?";
}

std::uint64_t TrialSeed(std::uint64_t run_seed, std::uint64_t index) {
  // SplitMix64 of the run seed advanced by the index.
  return ovpc::internal::MixBits(run_seed + ovpc::internal::kGoldenGamma * (index + 1));
}

}  // namespace ovpc::bench
