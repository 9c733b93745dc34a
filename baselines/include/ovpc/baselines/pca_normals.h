// Point normals by principal component analysis of a fixed-radius neighbourhood: the baseline of
// the paper's normal-estimation experiment (the eigenvalue method, as in PCL's NormalEstimation),
// written here on Eigen and nanoflann so that the build and the tests never need PCL.
#pragma once

#include <cstddef>
#include <vector>

#include "ovpc/core/types.h"

namespace ovpc::baselines {

struct PcaNormalsConfig {
  double radius_m = 0.3;   ///< neighbourhood radius (paper: 0.3 m); the point itself is included
  /// Points with fewer neighbours (itself included) get no normal. 3 is the least that spans a
  /// plane, and the rule PCL's NormalEstimation applies.
  int min_neighbours = 3;
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

struct PcaNormals {
  /// One per input point: the unit eigenvector of the smallest eigenvalue of the neighbourhood
  /// covariance, flipped so that it faces the viewpoint (n . (viewpoint - p) >= 0, the sign rule
  /// of PCL's flipNormalTowardsViewpoint). Vec3::Zero() when the point had too few neighbours or a
  /// non-finite coordinate (the project's convention for "no normal", as in TraversabilityCloud).
  std::vector<Vec3> normals;
  std::size_t num_without_normal = 0;
};

/// Estimates a normal for every point of `points`, neighbours within `config.radius_m` (strictly
/// closer) searched in a k-d tree over the same cloud. Non-finite points are neither queried nor
/// used as neighbours.
/// @throws std::invalid_argument for an invalid config or a non-finite viewpoint.
PcaNormals EstimatePcaNormals(const Points& points, const Vec3& viewpoint,
                              const PcaNormalsConfig& config);

/// The PCA normal of one neighbourhood (unit, unoriented), or Vec3::Zero() for fewer than three
/// points. Exposed for tests.
Vec3 PcaNormalOf(const Points& neighbourhood);

/// Flips `normal` to face `viewpoint` from `point` (n . (viewpoint - point) >= 0).
Vec3 FlipTowardsViewpoint(const Vec3& normal, const Vec3& point, const Vec3& viewpoint);

}  // namespace ovpc::baselines
