#include "ovpc/core/vertex_cloud.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>
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
  std::vector<std::uint8_t> foot;  // one per point, or empty (a cloud built from flags alone: no feet)
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

bool TraversabilityCloud::IsFoot(std::size_t i) const { return i < data_->foot.size() && data_->foot[i] != 0; }

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

void VertexNormals::Config::Validate() const {
  if (rule != Rule::kMeanOfFaces && rule != Rule::kPlaneFit) {
    throw std::invalid_argument("VertexNormals::Config: rule must be mean_of_faces or plane_fit");
  }
  if (!(radius_m > 0.0) || !std::isfinite(radius_m)) {
    throw std::invalid_argument("VertexNormals::Config: radius_m must be > 0 m and finite, got " + std::to_string(radius_m));
  }
  if (max_patch_points < 4 || max_patch_points > 256) {
    throw std::invalid_argument("VertexNormals::Config: max_patch_points must be in [4, 256], got " +
                                std::to_string(max_patch_points));
  }
}

namespace {

// Fewer points than this keep the mean-of-faces normal: three points always span a plane, so a
// patch of three says nothing about whether the surface is one (far away, where the visible points
// thin out, three of them 0.2-0.5 m apart with 5 cm of noise make a plane tilted by tens of degrees).
constexpr std::size_t kMinPatchPoints = 4;

// The plane fitted over the patch of `p` (see VertexNormals::Rule::kPlaneFit); `own` (the
// mean-of-faces normal) when the patch is not a plane. `patch` holds the patch's indices into
// `points`, `to_viewpoint` is the line of sight from p.
Vec3 PatchNormal(const Points& points, const Vec3& p, const Vec3& own, const Vec3& to_viewpoint,
                 const std::uint32_t* patch, std::size_t n) {
  if (n < kMinPatchPoints) return own;
  // Covariance about the patch's mean, from offsets to p (p is in the patch, so they stay small).
  Vec3 sum = Vec3::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 d = points[patch[k]] - p;
    sum += d;
    outer.noalias() += d * d.transpose();
  }
  const Vec3 mean = sum / static_cast<double>(n);
  const Eigen::Matrix3d covariance = outer / static_cast<double>(n) - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance);  // the closed form for a 3x3 matrix, no iterations
  const Vec3& values = solver.eigenvalues();
  if (solver.info() != Eigen::Success || !(values(0) < 0.25 * values(1))) return own;
  Vec3 fitted = solver.eigenvectors().col(0);
  const double norm = fitted.norm();
  if (!(norm > 0.0) || !fitted.allFinite()) return own;
  fitted /= norm;
  // The free side: the mean-of-faces normal's where the two lines agree within 60 deg; else (at
  // the rim of what was seen, where faces folding back to the far side outweigh the surface's own)
  // the viewpoint's, since the mesh is star-shaped around it and every line of sight runs through
  // free space. The line of sight alone would mislead at grazing angles, where the fit's own tilt
  // can exceed the angle of view.
  const double along_own = fitted.dot(own);
  const double side = std::abs(along_own) >= 0.5 ? along_own : fitted.dot(to_viewpoint);
  return side < 0.0 ? Vec3(-fitted) : fitted;
}

// Feet: non-traversable points each of whose non-traversable faces has another vertex more than
// kFootRiseM above the point and within kFootReachM of it in the plane, and none more than
// kFootToleranceM below it: every steep face at such a point rises from it, close by, higher than a
// step (the foot of a wall or a post). A lip is not a foot: its steep faces fall away from it. Nor
// is the rim of what was seen (a face to the viewpoint closes the hull there, over unseen space),
// nor a point with no observed face or whose faces' normal points down.
void MarkFeet(const FreeSpaceMesh& mesh, const std::vector<std::uint8_t>& traversable, const std::vector<Vec3>& normals,
              std::vector<std::uint8_t>* foot) {
  // The ground's range noise within one face (a few centimetres on the project's sensor).
  constexpr double kFootToleranceM = 0.05;
  // How far from the point, in the plane, the face rises to: at a wall's foot a few decimetres, and
  // from ground seen beside a wall's end, through a gap, up to its top edge 1-2 m (a 1.4 m wall, a
  // 2.2 m gap: VertexCloudMapTest.AWallsFootCarriesAWheelThroughAGap). A face from ground seen past
  // a 2 m post up to its top spans 2.2 m and more; its ground keeps its flag, since the face's tilt
  // spoils that ground's normal and poses there tilt (NavigatorTest.OneCycleMapsPlansAheadAndSetsOff
  // chose such a place as its goal and found no path to it).
  constexpr double kFootReachM = 2.0;
  // How high the face rises: more than a step (the height test's 0.25 m, the paper's delta_h_max),
  // so that what rises is an obstacle the vehicle's box meets, not the start of a slope. The foot of
  // a 35 deg ramp, whose faces rise a few centimetres to its next points, keeps its flag and with it
  // the wheels' distance from the ramp (slope_35_detour: 18 of 18 seeds kept off the ramp with
  // 0.25 m, 16 of 18 with 5 cm).
  constexpr double kFootRiseM = 0.25;
  const std::size_t n = traversable.size();
  foot->assign(n, 1);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    if (mesh.face_traversable[f]) continue;
    const auto& t = mesh.triangles[f];
    const bool closing = mesh.TouchesViewpoint(f);  // closes the hull over what was not seen
    for (int v : t) {
      if (v == mesh.viewpoint_vertex) continue;
      bool rises = false, falls = false;
      for (int w : t) {
        if (w == v || w == mesh.viewpoint_vertex) continue;
        const Vec3 d = mesh.vertices[w] - mesh.vertices[v];
        rises |= d.z() > kFootRiseM && d.head<2>().norm() <= kFootReachM;
        falls |= d.z() < -kFootToleranceM;
      }
      if (closing || falls || !rises) (*foot)[v] = 0;
    }
  }
  for (std::size_t i = 0; i < n; ++i) (*foot)[i] = (*foot)[i] && !traversable[i] && normals[i].z() > 0.0;
}

}  // namespace

TraversabilityCloud BuildTraversabilityCloud(const FreeSpaceMesh& mesh, const VertexNormals::Config& config) {
  config.Validate();
  const std::size_t n = mesh.num_visible();
  if (mesh.face_normals.size() != mesh.triangles.size() || mesh.face_traversable.size() != mesh.triangles.size()) {
    throw std::invalid_argument("BuildTraversabilityCloud: the mesh was not classified");
  }
  auto data = std::make_shared<TraversabilityCloud::Data>();
  std::vector<Vec3>& normals = data->normals;
  std::vector<std::uint8_t>& traversable = data->traversable;
  normals.assign(n, Vec3::Zero());
  traversable.assign(n, 1);
  std::vector<std::uint8_t> has_face(n, 0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const bool observed = !mesh.TouchesViewpoint(f);
    for (int v : mesh.triangles[f]) {
      if (v == mesh.viewpoint_vertex) continue;
      has_face[v] = 1;
      if (observed) normals[v] += mesh.face_normals[f];
      if (!mesh.face_traversable[f]) traversable[v] = 0;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double norm = normals[i].norm();
    normals[i] = norm > 0.0 ? Vec3(normals[i] / norm) : Vec3::Zero();
    if (!has_face[i] || norm == 0.0) traversable[i] = 0;
  }
  MarkFeet(mesh, traversable, normals, &data->foot);
  data->points.assign(mesh.vertices.begin(), mesh.vertices.begin() + static_cast<std::ptrdiff_t>(n));
  data->adaptor.points = &data->points;
  if (n == 0) return TraversabilityCloud(std::move(data));
  data->tree = std::make_unique<TraversabilityCloud::Data::Tree>(3, data->adaptor,
                                                                  nanoflann::KDTreeSingleIndexAdaptorParams(16));
  if (config.rule != VertexNormals::Rule::kPlaneFit) return TraversabilityCloud(std::move(data));

  // Plane fits on the cloud's own k-d tree: a k-nearest search bounded by the radius (the result
  // set's worst distance starts at radius^2, so the search prunes at the radius from the start),
  // the points visited in the tree's leaf order so that consecutive patches share cache lines.
  // The mean-of-faces normals are read (orientation, fallback) while the fitted ones are written.
  const std::vector<Vec3> own = normals;
  const auto k = static_cast<std::size_t>(config.max_patch_points);
  std::vector<std::uint32_t> patch(k);
  std::vector<double> dist2(k);
  // Points at exactly the radius count: the search admits only distances below the worst one.
  const double r2 = std::nextafter(config.radius_m * config.radius_m, std::numeric_limits<double>::infinity());
  const nanoflann::SearchParams params(32, 0.0f, false);
  for (const std::uint32_t i : data->tree->vAcc) {
    if (own[i].isZero(0.0)) continue;  // no observed face: nothing to orient a fit by
    const Vec3& p = data->points[i];
    nanoflann::KNNResultSet<double, std::uint32_t> result(k);
    result.init(patch.data(), dist2.data());
    dist2[k - 1] = r2;  // the bound until k points are found
    data->tree->findNeighbors(result, p.data(), params);
    normals[i] = PatchNormal(data->points, p, own[i], mesh.viewpoint - p, patch.data(), result.size());
  }
  return TraversabilityCloud(std::move(data));
}

}  // namespace ovpc
