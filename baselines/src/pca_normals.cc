#include "ovpc/baselines/pca_normals.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Eigenvalues>
#include <nanoflann.hpp>

namespace ovpc::baselines {
namespace {

/// nanoflann dataset adaptor over the finite points of a cloud (by index into `finite`).
struct Adaptor {
  const Points* points;
  const std::vector<std::uint32_t>* finite;
  std::size_t kdtree_get_point_count() const { return finite->size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return (*points)[(*finite)[i]][static_cast<int>(dim)];
  }
  template <class BBox>
  bool kdtree_get_bbox(BBox& /*bbox*/) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>,
                                                 Adaptor, 3, std::uint32_t>;

}  // namespace

void PcaNormalsConfig::Validate() const {
  if (!(radius_m > 0.0) || !std::isfinite(radius_m)) {
    throw std::invalid_argument("PcaNormalsConfig::radius_m must be finite and > 0");
  }
  if (min_neighbours < 3) {
    throw std::invalid_argument("PcaNormalsConfig::min_neighbours must be >= 3");
  }
}

Vec3 PcaNormalOf(const Points& neighbourhood) {
  if (neighbourhood.size() < 3) return Vec3::Zero();
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : neighbourhood) centroid += p;
  centroid /= static_cast<double>(neighbourhood.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : neighbourhood) {
    const Vec3 d = p - centroid;
    covariance.noalias() += d * d.transpose();
  }
  covariance /= static_cast<double>(neighbourhood.size());
  // Eigenvalues come back in ascending order: column 0 spans the direction of least spread.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  if (solver.info() != Eigen::Success) return Vec3::Zero();
  const Vec3 normal = solver.eigenvectors().col(0);
  const double norm = normal.norm();
  return norm > 0.0 && std::isfinite(norm) ? Vec3(normal / norm) : Vec3::Zero();
}

Vec3 FlipTowardsViewpoint(const Vec3& normal, const Vec3& point, const Vec3& viewpoint) {
  return normal.dot(viewpoint - point) < 0.0 ? Vec3(-normal) : normal;
}

PcaNormals EstimatePcaNormals(const Points& points, const Vec3& viewpoint,
                              const PcaNormalsConfig& config) {
  config.Validate();
  if (!viewpoint.allFinite()) {
    throw std::invalid_argument("EstimatePcaNormals: the viewpoint is not finite");
  }
  PcaNormals result;
  result.normals.assign(points.size(), Vec3::Zero());
  std::vector<std::uint32_t> finite;
  finite.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].allFinite()) finite.push_back(static_cast<std::uint32_t>(i));
  }
  result.num_without_normal = points.size() - finite.size();
  if (finite.empty()) return result;

  const Adaptor adaptor{&points, &finite};
  const Tree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  const double radius2 = config.radius_m * config.radius_m;
  nanoflann::SearchParams params;
  params.sorted = false;
  std::vector<std::pair<std::uint32_t, double>> found;
  Points neighbourhood;
  for (const std::uint32_t i : finite) {
    const Vec3& p = points[i];
    found.clear();
    tree.radiusSearch(p.data(), radius2, found, params);
    if (found.size() < static_cast<std::size_t>(config.min_neighbours)) {
      ++result.num_without_normal;
      continue;
    }
    neighbourhood.clear();
    for (const auto& f : found) neighbourhood.push_back(points[finite[f.first]]);
    const Vec3 normal = PcaNormalOf(neighbourhood);
    if (normal.isZero(0.0)) {
      ++result.num_without_normal;
      continue;
    }
    result.normals[i] = FlipTowardsViewpoint(normal, p, viewpoint);
  }
  return result;
}

}  // namespace ovpc::baselines
