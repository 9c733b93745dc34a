#include "ovpc/backends/column_map.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace ovpc::backends {
namespace {

// A normal this close to horizontal cannot carry the vehicle; the box then stays upright (as in
// VertexCloudMap).
constexpr double kMinNormalZ = 0.2;

void RequirePositive(double value, const char* field) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("ColumnMap::Config: ") + field + " must be > 0, got " + std::to_string(value));
  }
}

bool InRegion(const planner::SupportRegion& r, double c, double s, double x_m, double y_m) {
  if (r.empty()) return false;
  const double dx = x_m - r.pose.x_m, dy = y_m - r.pose.y_m;
  const double along = c * dx + s * dy, across = -s * dx + c * dy;
  return along >= r.min_x_m && along <= r.max_x_m && std::abs(across) <= r.half_width_m;
}

// Clips the parameter interval [*lo, *hi] to where low <= p + s a <= high.
bool Clip(double p, double a, double low, double high, double* lo, double* hi) {
  if (std::abs(a) < 1e-12) return p >= low && p <= high;
  double s0 = (low - p) / a, s1 = (high - p) / a;
  if (s0 > s1) std::swap(s0, s1);
  *lo = std::max(*lo, s0);
  *hi = std::min(*hi, s1);
  return *lo <= *hi;
}

}  // namespace

void ColumnGrid::Reset(double resolution, double origin_x, double origin_y, int columns_x, int columns_y) {
  resolution_m = resolution;
  origin_x_m = origin_x;
  origin_y_m = origin_y;
  nx = columns_x;
  ny = columns_y;
  ground_begin.assign(num_columns() + 1, 0);
  sample_begin.assign(num_columns() + 1, 0);
  ground_z.clear();
  sample_z.clear();
  sample_ground.clear();
}

void ColumnMap::Config::Validate() const {
  RequirePositive(max_projection_distance_m, "max_projection_distance_m");
  RequirePositive(normal_radius_m, "normal_radius_m");
}

ColumnMap::ColumnMap(ColumnGrid grid, const Config& config, const planner::GroundContext& ground,
                     const Traversability::Config& faces)
    : grid_(std::move(grid)), config_(config), ground_(ground), faces_(faces) {
  config_.Validate();
  ground_.Validate();
  if (!(faces_.alpha_max_rad > 0.0 && faces_.alpha_max_rad < kPi / 2)) {
    throw std::invalid_argument("ColumnMap: alpha_max_rad must be in (0, pi/2), got " + std::to_string(faces_.alpha_max_rad));
  }
  RequirePositive(faces_.delta_h_max_m, "delta_h_max_m");
  const ColumnGrid& g = grid_;
  if (!(g.resolution_m > 0.0) || g.nx < 0 || g.ny < 0 || g.ground_begin.size() != g.num_columns() + 1 ||
      g.sample_begin.size() != g.num_columns() + 1 || g.ground_begin.back() != g.ground_z.size() ||
      g.sample_begin.back() != g.sample_z.size() || g.sample_ground.size() != g.sample_z.size()) {
    throw std::invalid_argument("ColumnMap: the column grid's sizes do not match");
  }
  support_cos_ = std::cos(ground_.known_support.pose.yaw_rad);
  support_sin_ = std::sin(ground_.known_support.pose.yaw_rad);
  ground_column_.resize(g.ground_z.size());
  for (std::size_t c = 0; c < g.num_columns(); ++c) {
    for (std::uint32_t k = g.ground_begin[c]; k < g.ground_begin[c + 1]; ++k) ground_column_[k] = static_cast<int>(c);
  }
  // Bounds: the columns with occupied samples.
  int lo_x = g.nx, hi_x = -1, lo_y = g.ny, hi_y = -1;
  for (int iy = 0; iy < g.ny; ++iy) {
    for (int ix = 0; ix < g.nx; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy) * g.nx + ix;
      if (g.sample_begin[c] == g.sample_begin[c + 1]) continue;
      lo_x = std::min(lo_x, ix), hi_x = std::max(hi_x, ix), lo_y = std::min(lo_y, iy), hi_y = std::max(hi_y, iy);
    }
  }
  if (hi_x >= 0) {
    bounds_.min_x_m = g.origin_x_m + lo_x * g.resolution_m;
    bounds_.max_x_m = g.origin_x_m + (hi_x + 1) * g.resolution_m;
    bounds_.min_y_m = g.origin_y_m + lo_y * g.resolution_m;
    bounds_.max_y_m = g.origin_y_m + (hi_y + 1) * g.resolution_m;
  }
  Judge();
}

Vec3 ColumnMap::GroundPoint(int index) const {
  const int c = ground_column_[static_cast<std::size_t>(index)];
  return Vec3(grid_.CentreX(c % grid_.nx), grid_.CentreY(c / grid_.nx), grid_.ground_z[static_cast<std::size_t>(index)]);
}

std::vector<Vec3> ColumnMap::GroundPoints() const {
  std::vector<Vec3> points(grid_.ground_z.size());
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = GroundPoint(static_cast<int>(i));
  return points;
}

int ColumnMap::NearestInColumn(std::size_t column, double z) const {
  int best = -1;
  double best_dz = std::numeric_limits<double>::infinity();
  for (std::uint32_t k = grid_.ground_begin[column]; k < grid_.ground_begin[column + 1]; ++k) {
    const double dz = std::abs(grid_.ground_z[k] - z);
    if (dz < best_dz) best_dz = dz, best = static_cast<int>(k);  // ties: the lower one (sorted by height)
  }
  return best;
}

void ColumnMap::Judge() {
  const ColumnGrid& g = grid_;
  const std::size_t n = g.ground_z.size();
  normals_.assign(n, Vec3::UnitZ());
  traversable_.assign(n, 0);
  const double r = config_.normal_radius_m;
  const int reach = static_cast<int>(std::ceil(r / g.resolution_m));
  const double cos_alpha = std::cos(faces_.alpha_max_rad);
  for (std::size_t i = 0; i < n; ++i) {
    const int c = ground_column_[i];
    const int ix = c % g.nx, iy = c / g.nx;
    const double z = g.ground_z[i];
    // The plane through the candidates around it: per column within r in the plane, the candidate
    // nearest in height, if within r of it.
    Vec3 sum = Vec3::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    int count = 0;
    for (int jy = std::max(0, iy - reach); jy <= std::min(g.ny - 1, iy + reach); ++jy) {
      for (int jx = std::max(0, ix - reach); jx <= std::min(g.nx - 1, ix + reach); ++jx) {
        const double dx = (jx - ix) * g.resolution_m, dy = (jy - iy) * g.resolution_m;
        if (dx * dx + dy * dy > r * r) continue;
        const int k = NearestInColumn(static_cast<std::size_t>(jy) * g.nx + jx, z);
        if (k < 0 || std::abs(g.ground_z[static_cast<std::size_t>(k)] - z) > r) continue;
        const Vec3 d(dx, dy, g.ground_z[static_cast<std::size_t>(k)] - z);
        sum += d;
        outer += d * d.transpose();
        ++count;
      }
    }
    Vec3 normal = Vec3::UnitZ();
    if (count >= 3) {
      const Vec3 mean = sum / count;
      const Eigen::Matrix3d covariance = outer / count - mean * mean.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(covariance);
      const Eigen::Vector3d& values = solver.eigenvalues();
      if (solver.info() == Eigen::Success && values(0) < 0.25 * values(1)) {
        normal = solver.eigenvectors().col(0).normalized();
        if (normal.z() < 0.0) normal = -normal;
      }
    }
    normals_[i] = normal;
    // Slope, then the height steps to the eight neighbouring columns (their candidate nearest in
    // height; a column without one is not judged: a wall's or a post's columns hold no ground).
    bool ok = normal.z() > cos_alpha;
    for (int jy = iy - 1; ok && jy <= iy + 1; ++jy) {
      for (int jx = ix - 1; ok && jx <= ix + 1; ++jx) {
        if (jx < 0 || jy < 0 || jx >= g.nx || jy >= g.ny || (jx == ix && jy == iy)) continue;
        const int k = NearestInColumn(static_cast<std::size_t>(jy) * g.nx + jx, z);
        if (k >= 0 && !(std::abs(g.ground_z[static_cast<std::size_t>(k)] - z) < faces_.delta_h_max_m)) ok = false;
      }
    }
    traversable_[i] = ok ? 1 : 0;
  }
}

std::optional<ColumnMap::Candidate> ColumnMap::NearestGround(double x_m, double y_m, double z_m, double radius_m) const {
  const ColumnGrid& g = grid_;
  if (g.nx == 0 || g.ny == 0 || !std::isfinite(x_m) || !std::isfinite(y_m)) return std::nullopt;
  const double fx = std::floor((x_m - g.origin_x_m) / g.resolution_m), fy = std::floor((y_m - g.origin_y_m) / g.resolution_m);
  const int reach = static_cast<int>(std::ceil(radius_m / g.resolution_m)) + 1;
  if (fx < -reach || fy < -reach || fx > g.nx + reach || fy > g.ny + reach) return std::nullopt;
  const int cx = static_cast<int>(fx), cy = static_cast<int>(fy);
  // Rings of columns around the pose's own column, nearest first; a column's centre is nearest to
  // the points of its own column, so ring k holds nothing nearer than (k - 0.5) resolution.
  std::optional<Candidate> best;
  double best_d2 = radius_m * radius_m;
  for (int ring = 0; ring <= reach; ++ring) {
    if (best && (ring - 0.5) * g.resolution_m > std::sqrt(best_d2)) break;
    for (int jy = cy - ring; jy <= cy + ring; ++jy) {
      if (jy < 0 || jy >= g.ny) continue;
      const bool edge_row = jy == cy - ring || jy == cy + ring;
      for (int jx = cx - ring; jx <= cx + ring; jx += (edge_row || ring == 0) ? 1 : 2 * ring) {
        if (jx < 0 || jx >= g.nx) continue;
        const std::size_t c = static_cast<std::size_t>(jy) * g.nx + jx;
        if (g.ground_begin[c] == g.ground_begin[c + 1]) continue;
        const double dx = g.CentreX(jx) - x_m, dy = g.CentreY(jy) - y_m;
        const double d2 = dx * dx + dy * dy;
        if (d2 > best_d2 || (best && d2 == best_d2 && c >= static_cast<std::size_t>(best->iy) * g.nx + best->ix)) continue;
        best = Candidate{NearestInColumn(c, z_m), jx, jy};
        best_d2 = d2;
      }
    }
  }
  return best;
}

std::optional<planner::GroundPose> ColumnMap::Project(const planner::Pose2& pose) const {
  const auto found = NearestGround(pose.x_m, pose.y_m, ground_.ground_reference_z_m, config_.max_projection_distance_m);
  if (!found) return std::nullopt;
  const auto i = static_cast<std::size_t>(found->index);
  Vec3 normal = normals_[i];
  bool traversable = traversable_[i] != 0;
  if (!(normal.z() >= kMinNormalZ)) {
    normal = Vec3::UnitZ();
    traversable = false;
  }
  return planner::PoseOnPlane(pose, GroundPoint(found->index), normal, traversable);
}

int ColumnMap::Nearest3d(const Vec3& p, double radius_m, double* distance_m) const {
  const ColumnGrid& g = grid_;
  int best = -1;
  double best_d2 = radius_m * radius_m;
  if (g.nx == 0 || g.ny == 0) return best;
  const int x0 = static_cast<int>(std::max(0.0, std::floor((p.x() - radius_m - g.origin_x_m) / g.resolution_m)));
  const int x1 = static_cast<int>(std::min(g.nx - 1.0, std::floor((p.x() + radius_m - g.origin_x_m) / g.resolution_m)));
  const int y0 = static_cast<int>(std::max(0.0, std::floor((p.y() - radius_m - g.origin_y_m) / g.resolution_m)));
  const int y1 = static_cast<int>(std::min(g.ny - 1.0, std::floor((p.y() + radius_m - g.origin_y_m) / g.resolution_m)));
  for (int iy = y0; iy <= y1; ++iy) {
    for (int ix = x0; ix <= x1; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy) * g.nx + ix;
      for (std::uint32_t k = g.ground_begin[c]; k < g.ground_begin[c + 1]; ++k) {
        const double d2 = (Vec3(g.CentreX(ix), g.CentreY(iy), g.ground_z[k]) - p).squaredNorm();
        if (d2 <= best_d2 && (best < 0 || d2 < best_d2)) best_d2 = d2, best = static_cast<int>(k);
      }
    }
  }
  if (best >= 0 && distance_m) *distance_m = std::sqrt(best_d2);
  return best;
}

bool ColumnMap::SeenBeyond(const Vec3& contact, double radius_m) const {
  // The viewpoint is the map frame's origin.
  const double reach = contact.head<2>().norm();
  const ColumnGrid& g = grid_;
  const int x0 = static_cast<int>(std::max(0.0, std::floor((contact.x() - radius_m - g.origin_x_m) / g.resolution_m)));
  const int x1 = static_cast<int>(std::min(g.nx - 1.0, std::floor((contact.x() + radius_m - g.origin_x_m) / g.resolution_m)));
  const int y0 = static_cast<int>(std::max(0.0, std::floor((contact.y() - radius_m - g.origin_y_m) / g.resolution_m)));
  const int y1 = static_cast<int>(std::min(g.ny - 1.0, std::floor((contact.y() + radius_m - g.origin_y_m) / g.resolution_m)));
  for (int iy = y0; iy <= y1; ++iy) {
    for (int ix = x0; ix <= x1; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy) * g.nx + ix;
      for (std::uint32_t k = g.ground_begin[c]; k < g.ground_begin[c + 1]; ++k) {
        const Vec3 q(g.CentreX(ix), g.CentreY(iy), g.ground_z[k]);
        if (traversable_[k] && (q - contact).norm() <= radius_m && q.head<2>().norm() >= reach) return true;
      }
    }
  }
  return false;
}

planner::PoseCheck ColumnMap::CheckBox(const planner::GroundPose& ground, const planner::VehicleBox& vehicle) const {
  using planner::PoseCheck;
  // The box and the slab under its footprint in frame B, as VertexCloudMap::CheckBox.
  const planner::BoxExtent box = planner::BoxExtentAt(ground, vehicle);
  const double min_x = box.min_x_m, max_x = box.max_x_m, half_width = box.half_width_m, top = box.top_m;
  const double bottom = box.bottom_m;
  const double clearance = vehicle.ground_clearance_m;
  const ColumnGrid& g = grid_;
  if (g.sample_z.empty()) return PoseCheck::kValid;
  const bool all_points = vehicle.footprint_check == planner::VehicleBox::FootprintCheck::kAllPoints;

  // The columns under the planar bounding box of the eight corners (a column is vertical, so a
  // solid one meets the box only there too).
  const double lo_x = box.planar.min_x_m, hi_x = box.planar.max_x_m, lo_y = box.planar.min_y_m, hi_y = box.planar.max_y_m;
  const int ix0 = static_cast<int>(std::max(0.0, std::floor((lo_x - g.origin_x_m) / g.resolution_m)));
  const int ix1 = static_cast<int>(std::min(g.nx - 1.0, std::floor((hi_x - g.origin_x_m) / g.resolution_m)));
  const int iy0 = static_cast<int>(std::max(0.0, std::floor((lo_y - g.origin_y_m) / g.resolution_m)));
  const int iy1 = static_cast<int>(std::min(g.ny - 1.0, std::floor((hi_y - g.origin_y_m) / g.resolution_m)));
  const Eigen::Matrix3d R_B_L = ground.T_L_B.linear().transpose();
  const Vec3 t_L = ground.T_L_B.translation();
  const Vec3 up_B = R_B_L.col(2);  // the map's z axis in frame B (up_B.z() > 0 on any ground plane)
  const auto in_slab = [&](const Vec3& p_B) {
    return p_B.x() >= min_x && p_B.x() <= max_x && std::abs(p_B.y()) <= half_width && p_B.z() >= bottom && p_B.z() <= clearance;
  };
  bool ground_blocked = false;
  for (int iy = iy0; iy <= iy1; ++iy) {
    for (int ix = ix0; ix <= ix1; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy) * g.nx + ix;
      for (std::uint32_t k = g.sample_begin[c]; k < g.sample_begin[c + 1]; ++k) {
        const Vec3 p_B = R_B_L * (Vec3(g.CentreX(ix), g.CentreY(iy), g.sample_z[k]) - t_L);
        const std::int32_t under = g.sample_ground[k];
        const bool ground_ok = under >= 0 && traversable_[static_cast<std::size_t>(under)];
        if (!g.solid_below) {
          if (p_B.x() < min_x || p_B.x() > max_x || std::abs(p_B.y()) > half_width || p_B.z() < bottom || p_B.z() > top) continue;
          if (p_B.z() > clearance) return PoseCheck::kCollision;
          if (all_points && !ground_ok) ground_blocked = true;
          continue;
        }
        // A solid column: p_B + s up_B for s <= 0. Where it is inside the footprint (an interval of
        // s), its highest point must stay at or below the clearance, unless that part of it lies
        // wholly above the box.
        double lo = -std::numeric_limits<double>::infinity(), hi = 0.0;
        if (!Clip(p_B.x(), up_B.x(), min_x, max_x, &lo, &hi) || !Clip(p_B.y(), up_B.y(), -half_width, half_width, &lo, &hi)) {
          continue;
        }
        const double z_hi = p_B.z() + hi * up_B.z(), z_lo = p_B.z() + lo * up_B.z();
        if (z_hi > clearance && z_lo <= top) return PoseCheck::kCollision;
        if (all_points && !ground_ok && in_slab(p_B)) ground_blocked = true;
      }
    }
  }
  if (ground_blocked) return PoseCheck::kGroundUnderFootprint;
  if (all_points) return PoseCheck::kValid;
  // Each wheel on known traversable ground, as VertexCloudMap: its contact point near a ground
  // candidate, and that candidate traversable.
  for (double x : {0.0, vehicle.wheelbase_m}) {
    for (double y : {-0.5 * vehicle.track_m, 0.5 * vehicle.track_m}) {
      const Vec3 contact = ground.T_L_B * Vec3(x, y, 0.0);
      if (InRegion(ground_.known_support, support_cos_, support_sin_, contact.x(), contact.y())) continue;
      double distance = 0.0;
      const int nearest = Nearest3d(contact, vehicle.wheel_support_m, &distance);
      if (nearest < 0) return PoseCheck::kUnseenGround;
      if (!traversable_[static_cast<std::size_t>(nearest)]) return PoseCheck::kGroundUnderFootprint;
      if (distance > vehicle.edge_tolerance_m && !SeenBeyond(contact, vehicle.wheel_support_m)) {
        return PoseCheck::kUnseenGround;
      }
    }
  }
  return PoseCheck::kValid;
}

bool ColumnMap::IsKnownFree(double x_m, double y_m) const {
  if (!bounds_.Contains(x_m, y_m)) return false;
  const auto ground = Project(planner::Pose2{x_m, y_m, 0.0});
  return ground && ground->traversable;
}

}  // namespace ovpc::backends
