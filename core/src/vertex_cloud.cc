#include "ovpc/core/vertex_cloud.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include <nanoflann.hpp>

namespace ovpc {

struct TraversabilityCloud::Data {
  // nanoflann dataset adaptor over the point vector.
  struct Adaptor {
    const Points* points;
    std::size_t kdtree_get_point_count() const { return points->size(); }
    double kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*points)[i][static_cast<int>(dim)]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox& /*bbox*/) const { return false; }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3,
                                                   std::uint32_t>;

  Points points;
  std::vector<Vec3> normals;
  std::vector<std::uint8_t> traversable;
  Adaptor adaptor{&points};
  std::unique_ptr<Tree> tree;
};

TraversabilityCloud::TraversabilityCloud()
    : TraversabilityCloud(Points{}, std::vector<Vec3>{}, std::vector<std::uint8_t>{}) {}

TraversabilityCloud::TraversabilityCloud(Points points, std::vector<Vec3> normals,
                                         std::vector<std::uint8_t> traversable) {
  if (normals.size() != points.size() || traversable.size() != points.size()) {
    throw std::invalid_argument("TraversabilityCloud: points, normals and flags differ in size");
  }
  // Built in place on the heap: the tree refers to the adaptor, which refers to the points.
  auto data = std::make_shared<Data>();
  data->points = std::move(points);
  data->normals = std::move(normals);
  data->traversable = std::move(traversable);
  data->adaptor.points = &data->points;
  if (!data->points.empty()) {
    data->tree = std::make_unique<Data::Tree>(3, data->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  }
  data_ = std::move(data);
}

std::size_t TraversabilityCloud::size() const { return data_->points.size(); }
const Points& TraversabilityCloud::points() const { return data_->points; }
const std::vector<Vec3>& TraversabilityCloud::normals() const { return data_->normals; }
const std::vector<std::uint8_t>& TraversabilityCloud::traversable() const { return data_->traversable; }

std::optional<TraversabilityCloud::Neighbor> TraversabilityCloud::Nearest(const Vec3& query) const {
  if (!data_->tree || !query.allFinite()) return std::nullopt;
  std::uint32_t index = 0;
  double dist2 = 0.0;
  nanoflann::KNNResultSet<double, std::uint32_t> result(1);
  result.init(&index, &dist2);
  data_->tree->findNeighbors(result, query.data(), nanoflann::SearchParams());
  return Neighbor{static_cast<int>(index), std::sqrt(dist2)};
}

void TraversabilityCloud::KNearest(const Vec3& query, std::size_t k, std::vector<Neighbor>* out) const {
  out->clear();
  if (!data_->tree || !query.allFinite() || k == 0) return;
  thread_local std::vector<std::uint32_t> indices;
  thread_local std::vector<double> dist2;
  indices.resize(k);
  dist2.resize(k);
  nanoflann::KNNResultSet<double, std::uint32_t> result(k);
  result.init(indices.data(), dist2.data());
  data_->tree->findNeighbors(result, query.data(), nanoflann::SearchParams());
  for (std::size_t i = 0; i < result.size(); ++i) out->push_back({static_cast<int>(indices[i]), std::sqrt(dist2[i])});
}

std::vector<TraversabilityCloud::Neighbor> TraversabilityCloud::WithinRadius(const Vec3& query,
                                                                             double radius_m) const {
  std::vector<Neighbor> out;
  if (!data_->tree || !query.allFinite() || !(radius_m > 0.0)) return out;
  std::vector<std::pair<std::uint32_t, double>> found;
  nanoflann::SearchParams params;
  params.sorted = true;
  data_->tree->radiusSearch(query.data(), radius_m * radius_m, found, params);
  out.reserve(found.size());
  for (const auto& f : found) out.push_back({static_cast<int>(f.first), std::sqrt(f.second)});
  return out;
}

std::vector<int> TraversabilityCloud::InBox(const Eigen::Isometry3d& T_L_B, const Vec3& half_extents_m) const {
  std::vector<int> out;
  if (!data_->tree || !T_L_B.matrix().allFinite() || !(half_extents_m.minCoeff() >= 0.0)) return out;
  const Vec3 centre_L = T_L_B.translation();
  const double r = half_extents_m.norm();
  std::vector<std::pair<std::uint32_t, double>> found;
  nanoflann::SearchParams params;
  params.sorted = false;
  data_->tree->radiusSearch(centre_L.data(), r * r * (1.0 + 1e-12), found, params);
  const Eigen::Isometry3d T_B_L = T_L_B.inverse();
  for (const auto& f : found) {
    const Vec3 p_B = T_B_L * data_->points[f.first];
    if ((p_B.cwiseAbs().array() <= half_extents_m.array()).all()) out.push_back(static_cast<int>(f.first));
  }
  std::sort(out.begin(), out.end());
  return out;
}

TraversabilityCloud BuildTraversabilityCloud(const FreeSpaceMesh& mesh) {
  const std::size_t n = mesh.num_visible();
  if (mesh.face_normals.size() != mesh.triangles.size() || mesh.face_traversable.size() != mesh.triangles.size()) {
    throw std::invalid_argument("BuildTraversabilityCloud: the mesh was not classified");
  }
  std::vector<Vec3> normal_sum(n, Vec3::Zero());
  std::vector<std::uint8_t> traversable(n, 1);
  std::vector<std::uint8_t> has_face(n, 0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const bool observed = !mesh.TouchesViewpoint(f);
    for (int v : mesh.triangles[f]) {
      if (v == mesh.viewpoint_vertex) continue;
      has_face[v] = 1;
      if (observed) normal_sum[v] += mesh.face_normals[f];
      if (!mesh.face_traversable[f]) traversable[v] = 0;
    }
  }
  std::vector<Vec3> normals(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double norm = normal_sum[i].norm();
    normals[i] = norm > 0.0 ? Vec3(normal_sum[i] / norm) : Vec3::Zero();
    if (!has_face[i] || norm == 0.0) traversable[i] = 0;
  }
  Points points(mesh.vertices.begin(), mesh.vertices.begin() + static_cast<std::ptrdiff_t>(n));
  return TraversabilityCloud(std::move(points), std::move(normals), std::move(traversable));
}

}  // namespace ovpc
