// The paper's normal-estimation experiment ("Evaluation in simulation"): a flat ground and an
// inclined plane of slope alpha, sampled as five noisy, misaligned clouds bundled into one, and
// the angular error of estimated normals against the true normal of the surface each point was
// sampled from. The protocol's figures are in docs/REFERENCE.md; the choices the paper leaves
// open are named below and in docs/PAPER_REPRODUCTION.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "ovpc/baselines/pca_normals.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/core/types.h"

namespace ovpc::bench {

/// The scene, in the world frame W: z up, the robot's base at the origin on the ground.
/// Ground z = 0 for x < slope_start_x_m; from there an inclined plane rises along +x with slope
/// alpha, z = (x - slope_start_x_m) tan(alpha), out to the scene's edge. Both span
/// |y| <= half_extent_m, and together |x| <= half_extent_m (the 20 m x 20 m footprint).
struct SlopeSceneConfig {
  double half_extent_m = 10.0;     ///< 20 m x 20 m scene (paper)
  /// Where the inclined plane starts. Assumption: the paper does not say; 3 m in front of the
  /// robot leaves 13 m x 20 m of ground and a 7 m (horizontal) x 20 m slope.
  double slope_start_x_m = 3.0;
  double spacing_m = 0.2;          ///< grid step along each surface (paper)
  double noise_m = 0.05;           ///< uniform noise in [-noise, noise] per axis and point (paper)
  int num_clouds = 5;              ///< clouds bundled (paper)
  double pose_error_deg = 0.5;     ///< per cloud, uniform in [-e, e] about each axis (paper)
  double pose_error_m = 0.1;       ///< per cloud, uniform in [-e, e] along each axis (paper)
  double viewpoint_height_m = 1.88;  ///< viewpoint above the ground at the centre (paper)
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

enum class Surface : std::uint8_t { kGround = 0, kSlope = 1 };

struct SlopeScene {
  double alpha_rad = 0.0;
  Points points;                 ///< the bundled cloud in W
  std::vector<Surface> surface;  ///< per point: the surface it was sampled from
  Vec3 viewpoint = Vec3::Zero();
  Vec3 ground_normal = Vec3::UnitZ();
  Vec3 slope_normal = Vec3::UnitZ();  ///< (-sin alpha, 0, cos alpha)
  const Vec3& TrueNormal(std::size_t i) const {
    return surface[i] == Surface::kGround ? ground_normal : slope_normal;
  }
};

/// The unit normal of the inclined plane of slope `alpha_rad` rising along +x.
Vec3 SlopeNormal(double alpha_rad);

/// The noise-free samples of one cloud: a grid of step spacing_m on the ground (x from
/// -half_extent_m, strictly before the slope's foot) and on the inclined plane (along the slope
/// from its foot, up to the scene's edge in x), y from -half_extent_m to half_extent_m.
void SampleSurfaces(double alpha_rad, const SlopeSceneConfig& config, Points* points,
                    std::vector<Surface>* surface);

/// The bundled cloud: for each of num_clouds clouds, the surface samples with uniform noise per
/// axis, then a rigid pose error about the viewpoint, p <- v + R (p - v) + t (R from uniform roll,
/// pitch and yaw errors, t uniform per axis) — the error of a misregistered scan. Deterministic
/// from `seed` on one platform (standard library distributions).
/// @throws std::invalid_argument for an invalid config or alpha outside [0, 90) degrees.
SlopeScene MakeSlopeScene(double alpha_rad, const SlopeSceneConfig& config, std::uint64_t seed);

/// Angle in degrees between an estimated and a true normal, as oriented vectors (so a flipped
/// normal counts as an error near 180 deg, as it would for traversability). Neither needs to be
/// unit. NaN when the estimate is zero or not finite ("no normal").
double AngularErrorDeg(const Vec3& estimate, const Vec3& truth);

/// The error of a normal taken as an unoriented line: min(e, 180 - e) for an oriented error e in
/// degrees (a flipped normal counts as correct). A diagnostic: the experiment's metric is oriented.
double UnorientedDeg(double oriented_error_deg);

/// A per-point angular error.
struct PointError {
  std::size_t index = 0;  ///< into the evaluated cloud (SlopeScene::points unless filtered)
  double error_deg = 0.0;
  Vec3 position = Vec3::Zero();
  Surface surface = Surface::kGround;  ///< whose normal was the truth
};

/// Errors of one method on one scene.
struct MethodErrors {
  std::vector<PointError> errors;   ///< points that got a normal
  std::size_t without_normal = 0;   ///< points the method evaluated but gave no normal
  double ms = 0.0;                  ///< wall clock of the estimation
  std::vector<double> Degrees() const;
};

/// Normal estimator under test: one normal per point (Vec3::Zero() for none), given the cloud and
/// the viewpoint.
using NormalEstimator = std::function<baselines::PcaNormals(const Points&, const Vec3&)>;

/// Optional preprocessing of the OVPC input with the point cloud buffer's voxel filter
/// (VoxelFilter: one centroid per voxel holding at least min_hits points). Off by default: the
/// protocol gives OVPC the bundled cloud as it is. A diagnostic of how much the buffer's filter
/// changes the figures; the PCA baseline always gets the unfiltered cloud.
struct OvpcInputFilter {
  double voxel_size_m = 0.0;  ///< <= 0: no filter
  int min_hits = 2;
};

struct NormalsTrial {
  double alpha_deg = 0.0;
  std::uint64_t seed = 0;
  std::size_t points = 0;
  std::size_t ovpc_input_points = 0;  ///< points given to OVPC (fewer when filtered)
  GhprStatus ovpc_status = GhprStatus::kOk;
  /// OVPC: the visible points (mesh vertices); the others have no vertex normal and are not
  /// evaluated. A visible point whose faces all touch the viewpoint has no normal.
  MethodErrors ovpc;
  /// With `other_normals` given: the same mesh's vertex normals under that rule, scored the same
  /// way (its `ms` is BuildTraversabilityCloud's alone, the rest of the update being shared).
  MethodErrors ovpc_other;
  MethodErrors pca;          ///< PCA on every point of the bundled cloud
  /// The same PCA errors restricted to OVPC's visible points (empty when OVPC's input was
  /// filtered: its points are then voxel centroids, not points of the cloud).
  MethodErrors pca_visible;
};

/// Errors of vertex normals of `map` (built from `scene.points`, which the mapper must have used
/// unchanged) against the truth.
/// @throws std::logic_error if the mapper dropped points (indices would not match).
MethodErrors OvpcErrors(const SlopeScene& scene, const OvpcMap& map);

/// The surface under a position that is not a sample (a voxel centroid): the slope from
/// slope_start_x_m on, the ground before it.
Surface SurfaceAt(const Vec3& position, const SlopeSceneConfig& config);

/// Errors of vertex normals of `map` built from any cloud of the scene (e.g. filtered), each
/// against the normal of the surface under the vertex (SurfaceAt).
MethodErrors OvpcErrorsByPosition(const SlopeScene& scene, const SlopeSceneConfig& config,
                                  const OvpcMap& map);

/// Errors of per-point normals against the truth.
MethodErrors PointNormalErrors(const SlopeScene& scene, const baselines::PcaNormals& normals);

/// One slope: builds the scene from `seed`, runs the OVPC update from the viewpoint (on the
/// bundled cloud, or on its voxel-filtered version if `filter` says so) and the PCA estimator, and
/// returns both methods' errors; with `other_normals`, also the errors of the same mesh's vertex
/// normals under that rule (NormalsTrial::ovpc_other).
NormalsTrial RunNormalsTrial(double alpha_deg, const SlopeSceneConfig& scene_config,
                             const OvpcMapper& mapper, const NormalEstimator& pca,
                             std::uint64_t seed, const OvpcInputFilter& filter = {},
                             const VertexNormals::Config* other_normals = nullptr);

/// The vertex-normal rules by their names in files, as VertexNormals::Config declares them.
std::map<std::string, VertexNormals::Rule> VertexNormalRules();
/// A rule's name in files ("?" for a value that is none of them).
std::string VertexNormalRuleName(VertexNormals::Rule rule);

/// The seed of trial `index` from the run's seed (SplitMix64 of both), so trials are independent
/// and any one of them can be re-run alone.
std::uint64_t TrialSeed(std::uint64_t run_seed, std::uint64_t index);

}  // namespace ovpc::bench
