// PCL's NormalEstimation behind the project's types: the reference the Eigen PCA baseline
// (pca_normals.h) is checked against. Built only when PCL is installed
// (`scripts/install-deps --with-baselines`), as the target ovpc::baselines_pcl; its users get the
// compile definition OVPC_HAVE_PCL. No PCL type appears in this header.
#pragma once

#include "ovpc/baselines/pca_normals.h"

namespace ovpc::baselines {

/// Normals by `pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal>` with a radius search of
/// `config.radius_m` in a `pcl::search::KdTree` and the viewpoint set to `viewpoint` (so normals
/// are flipped towards it). Points PCL leaves without a normal (NaN: fewer than three neighbours)
/// get Vec3::Zero(), as in EstimatePcaNormals. PCL computes in single precision.
/// `config.min_neighbours` must be 3 (PCL's fixed rule).
/// @throws std::invalid_argument for an invalid config, min_neighbours != 3 or a non-finite
///         viewpoint.
PcaNormals EstimatePclNormals(const Points& points, const Vec3& viewpoint,
                              const PcaNormalsConfig& config);

}  // namespace ovpc::baselines
