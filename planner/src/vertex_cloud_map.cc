#include "ovpc/planner/vertex_cloud_map.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace ovpc::planner {
namespace {

// A normal this close to horizontal cannot carry the vehicle; the box then stays upright.
constexpr double kMinNormalZ = 0.2;
// Grid cells for the box test: about the ground point spacing times two, and never more than
// kMaxCells cells along a side, whatever the map's extent.
constexpr double kCellM = 0.5;
constexpr int kMaxCells = 512;

}  // namespace

namespace {

bool InRegion(const SupportRegion& r, double c, double s, double x_m, double y_m) {
  if (r.empty()) return false;
  const double dx = x_m - r.pose.x_m, dy = y_m - r.pose.y_m;
  const double along = c * dx + s * dy, across = -s * dx + c * dy;
  return along >= r.min_x_m && along <= r.max_x_m && std::abs(across) <= r.half_width_m;
}

}  // namespace

bool SupportRegion::Contains(double x_m, double y_m) const {
  return InRegion(*this, std::cos(pose.yaw_rad), std::sin(pose.yaw_rad), x_m, y_m);
}

RememberedGround::RememberedGround(const std::vector<Vec3>& points_L, const std::vector<std::uint8_t>& traversable) {
  if (points_L.size() != traversable.size()) throw std::invalid_argument("RememberedGround: one flag per point");
  if (points_L.empty()) return;
  double lo_x = std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  for (const Vec3& p : points_L) {
    if (!p.allFinite()) throw std::invalid_argument("RememberedGround: a point is not finite");
    lo_x = std::min(lo_x, p.x()), hi_x = std::max(hi_x, p.x());
    lo_y = std::min(lo_y, p.y()), hi_y = std::max(hi_y, p.y());
  }
  if (hi_x - lo_x > 1000.0 || hi_y - lo_y > 1000.0) throw std::invalid_argument("RememberedGround: the points span too far");
  origin_x_m_ = lo_x, origin_y_m_ = lo_y;
  nx_ = static_cast<int>(std::floor((hi_x - lo_x) / kCellM)) + 1;
  ny_ = static_cast<int>(std::floor((hi_y - lo_y) / kCellM)) + 1;
  std::vector<std::uint32_t> cell_of(points_L.size());
  cell_begin_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
  for (std::size_t i = 0; i < points_L.size(); ++i) {
    const int ix = std::min(nx_ - 1, static_cast<int>((points_L[i].x() - lo_x) / kCellM));
    const int iy = std::min(ny_ - 1, static_cast<int>((points_L[i].y() - lo_y) / kCellM));
    cell_of[i] = static_cast<std::uint32_t>(iy * nx_ + ix);
    ++cell_begin_[cell_of[i] + 1];
  }
  for (std::size_t c = 1; c < cell_begin_.size(); ++c) cell_begin_[c] += cell_begin_[c - 1];
  std::vector<std::uint32_t> next(cell_begin_.begin(), cell_begin_.end() - 1);
  points_.resize(points_L.size());
  traversable_.resize(points_L.size());
  for (std::size_t i = 0; i < points_L.size(); ++i) {
    const std::uint32_t k = next[cell_of[i]]++;
    points_[k] = points_L[i];
    traversable_[k] = traversable[i];
  }
}

bool RememberedGround::Carries(const Vec3& p, double radius_m, double dz_m) const {
  if (points_.empty()) return false;
  const int ix0 = std::max(0, static_cast<int>(std::floor((p.x() - radius_m - origin_x_m_) / kCellM)));
  const int ix1 = std::min(nx_ - 1, static_cast<int>(std::floor((p.x() + radius_m - origin_x_m_) / kCellM)));
  const int iy0 = std::max(0, static_cast<int>(std::floor((p.y() - radius_m - origin_y_m_) / kCellM)));
  const int iy1 = std::min(ny_ - 1, static_cast<int>(std::floor((p.y() + radius_m - origin_y_m_) / kCellM)));
  const double r2 = radius_m * radius_m;
  double best = r2;
  std::optional<std::uint32_t> nearest;
  for (int iy = iy0; iy <= iy1; ++iy) {
    for (int ix = ix0; ix <= ix1; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(ix);
      for (std::uint32_t k = cell_begin_[c]; k < cell_begin_[c + 1]; ++k) {
        const double d2 = (points_[k] - p).squaredNorm();
        // A lip: non-traversable ground remembered anywhere within the support (a wall just below
        // it, a drop's face) carries no wheel from memory, however near the lip's top is.
        if (d2 <= r2 && !traversable_[k]) return false;
        if (d2 <= best) best = d2, nearest = k;  // the last of equals: cells and points in a fixed order
      }
    }
  }
  return nearest && std::abs(points_[*nearest].z() - p.z()) <= dz_m;
}

void GroundContext::Validate() const {
  if (!std::isfinite(ground_reference_z_m)) throw std::invalid_argument("GroundContext: ground_reference_z_m must be finite");
  const SupportRegion& r = known_support;
  if (!std::isfinite(r.pose.x_m) || !std::isfinite(r.pose.y_m) || !std::isfinite(r.pose.yaw_rad) ||
      !std::isfinite(r.min_x_m) || !std::isfinite(r.max_x_m) || !std::isfinite(r.half_width_m)) {
    throw std::invalid_argument("GroundContext: known_support must be finite");
  }
}

void VertexCloudMap::Config::Validate() const {
  if (normal_neighbours < 1 || normal_neighbours > 64) {
    throw std::invalid_argument("VertexCloudMap::Config: normal_neighbours must be in [1, 64], got " +
                                std::to_string(normal_neighbours));
  }
  if (!(normal_radius_m >= 0.0) || !std::isfinite(normal_radius_m)) {
    throw std::invalid_argument("VertexCloudMap::Config: normal_radius_m must be >= 0, got " + std::to_string(normal_radius_m));
  }
  if (!(max_projection_distance_m > 0.0) || !std::isfinite(max_projection_distance_m)) {
    throw std::invalid_argument("VertexCloudMap::Config: max_projection_distance_m must be > 0, got " +
                                std::to_string(max_projection_distance_m));
  }
}

VertexCloudMap::VertexCloudMap(TraversabilityCloud cloud, const Config& config, const GroundContext& ground)
    : cloud_(std::move(cloud)), config_(config), ground_(ground) {
  config_.Validate();
  ground_.Validate();
  for (std::size_t i = 0; i < cloud_.size(); ++i) {
    if (!cloud_.points()[i].allFinite() || !cloud_.normals()[i].allFinite()) {
      throw std::invalid_argument("VertexCloudMap: point " + std::to_string(i) + " of the cloud is not finite");
    }
  }
  if (config_.normal_neighbours > 1) fits_ = std::make_shared<FitCache>(cloud_.size());
  support_cos_ = std::cos(ground_.known_support.pose.yaw_rad);
  support_sin_ = std::sin(ground_.known_support.pose.yaw_rad);
  if (cloud_.empty()) return;  // empty bounds: every pose is outside the map
  bounds_.min_x_m = bounds_.min_y_m = std::numeric_limits<double>::infinity();
  bounds_.max_x_m = bounds_.max_y_m = -std::numeric_limits<double>::infinity();
  for (const Vec3& p : cloud_.points()) {
    bounds_.min_x_m = std::min(bounds_.min_x_m, p.x());
    bounds_.max_x_m = std::max(bounds_.max_x_m, p.x());
    bounds_.min_y_m = std::min(bounds_.min_y_m, p.y());
    bounds_.max_y_m = std::max(bounds_.max_y_m, p.y());
  }

  Grid& g = grid_;
  const double extent = std::max(bounds_.max_x_m - bounds_.min_x_m, bounds_.max_y_m - bounds_.min_y_m);
  g.cell_m = std::max(kCellM, extent / (kMaxCells - 1));
  g.origin_x_m = bounds_.min_x_m;
  g.origin_y_m = bounds_.min_y_m;
  g.nx = static_cast<int>((bounds_.max_x_m - bounds_.min_x_m) / g.cell_m) + 1;
  g.ny = static_cast<int>((bounds_.max_y_m - bounds_.min_y_m) / g.cell_m) + 1;
  const auto cell_of = [&g](const Vec3& p) {
    const int ix = std::min(g.nx - 1, static_cast<int>((p.x() - g.origin_x_m) / g.cell_m));
    const int iy = std::min(g.ny - 1, static_cast<int>((p.y() - g.origin_y_m) / g.cell_m));
    return static_cast<std::size_t>(iy) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(ix);
  };
  const std::size_t num_cells = static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny);
  g.cell_begin.assign(num_cells + 1, 0);
  for (const Vec3& p : cloud_.points()) ++g.cell_begin[cell_of(p) + 1];
  for (std::size_t c = 0; c < num_cells; ++c) g.cell_begin[c + 1] += g.cell_begin[c];
  std::vector<std::uint32_t> next(g.cell_begin.begin(), g.cell_begin.end() - 1);
  std::vector<std::uint32_t> order(cloud_.size());
  for (std::size_t i = 0; i < cloud_.size(); ++i) order[next[cell_of(cloud_.points()[i])]++] = static_cast<std::uint32_t>(i);
  // Each cell's points by height (ties by index), so that the box test can skip the points of a cell
  // that lie below or above the box's height band.
  const auto lower = [this](std::uint32_t a, std::uint32_t b) {
    const double za = cloud_.points()[a].z(), zb = cloud_.points()[b].z();
    return za < zb || (za == zb && a < b);
  };
  for (std::size_t c = 0; c < num_cells; ++c) std::sort(order.begin() + g.cell_begin[c], order.begin() + g.cell_begin[c + 1], lower);
  g.points.resize(cloud_.size());
  g.traversable.resize(cloud_.size());
  for (std::size_t slot = 0; slot < order.size(); ++slot) {
    g.points[slot] = cloud_.points()[order[slot]];
    g.traversable[slot] = cloud_.traversable()[order[slot]];
  }
}

std::optional<int> VertexCloudMap::NearestIndex(const Pose2& pose) const {
  // Nearest visible point to the pose at the reference height, then again at the height found: on a
  // slope the first answer lies uphill or downhill of the pose, the second is close below it.
  const auto first = cloud_.Nearest(Vec3(pose.x_m, pose.y_m, ground_.ground_reference_z_m));
  if (!first) return std::nullopt;
  const Vec3 query(pose.x_m, pose.y_m, cloud_.points()[first->index].z());
  const auto nearest = cloud_.Nearest(query);
  if (!nearest || nearest->distance_m > config_.max_projection_distance_m) return std::nullopt;
  return nearest->index;
}

GroundPose VertexCloudMap::OnPlane(const Pose2& pose, int index, Vec3 normal) const {
  bool traversable = cloud_.traversable()[static_cast<std::size_t>(index)] != 0;
  if (!(normal.z() >= kMinNormalZ)) {
    normal = Vec3::UnitZ();
    traversable = false;
  }
  return PoseOnPlane(pose, cloud_.points()[static_cast<std::size_t>(index)], normal, traversable);
}

std::optional<GroundPose> VertexCloudMap::Project(const Pose2& pose) const {
  const std::optional<int> index = NearestIndex(pose);
  if (!index) return std::nullopt;
  return OnPlane(pose, *index, cloud_.normals()[static_cast<std::size_t>(*index)]);
}

std::optional<GroundPose> VertexCloudMap::ProjectForBox(const Pose2& pose) const {
  if (config_.normal_neighbours <= 1) return Project(pose);
  const std::optional<int> index = NearestIndex(pose);
  if (!index) return std::nullopt;
  const auto i = static_cast<std::size_t>(*index);
  std::atomic<std::uint8_t>& state = fits_->state[i];
  if (state.load(std::memory_order_acquire) == 2) return OnPlane(pose, *index, fits_->normal[i]);
  const Vec3 normal = FittedNormal(*index);
  std::uint8_t empty = 0;
  if (state.compare_exchange_strong(empty, 1, std::memory_order_acq_rel)) {
    fits_->normal[i] = normal;
    state.store(2, std::memory_order_release);
  }
  return OnPlane(pose, *index, normal);
}

Vec3 VertexCloudMap::FittedNormal(int index) const {
  const Vec3& p = cloud_.points()[static_cast<std::size_t>(index)];
  const Vec3& own = cloud_.normals()[static_cast<std::size_t>(index)];
  if (!(own.z() >= kMinNormalZ)) return own;
  // The least-squares plane through the point and those of its normal_neighbours nearest within
  // normal_radius_m: its normal is the covariance's eigenvector of the smallest eigenvalue, turned to
  // the side of the point's own normal. Fewer than three points, or no clear plane (a line of
  // points, a blob), keep the point's own normal.
  thread_local std::vector<TraversabilityCloud::Neighbor> neighbours;
  cloud_.KNearest(p, static_cast<std::size_t>(config_.normal_neighbours), &neighbours);
  const double r2 = config_.normal_radius_m * config_.normal_radius_m;
  Vec3 sum = Vec3::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  int n = 0;
  for (const TraversabilityCloud::Neighbor& nb : neighbours) {
    const Vec3 d = cloud_.points()[static_cast<std::size_t>(nb.index)] - p;
    if (d.squaredNorm() > r2) continue;
    sum += d;
    outer += d * d.transpose();
    ++n;
  }
  if (n < 3) return own;
  const Vec3 mean = sum / n;
  const Eigen::Matrix3d covariance = outer / n - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance);
  const Eigen::Vector3d& values = solver.eigenvalues();
  if (solver.info() != Eigen::Success || !(values(0) < 0.25 * values(1))) return own;
  Vec3 fitted = solver.eigenvectors().col(0);
  if (fitted.dot(own) < 0.0) fitted = -fitted;
  return fitted.z() >= kMinNormalZ ? Vec3(fitted.normalized()) : own;
}

PoseCheck VertexCloudMap::CheckBox(const GroundPose& ground, const VehicleBox& vehicle) const {
  // The vehicle box and the slab under its footprint, in frame B: x along the heading from the rear
  // axle, z along the ground normal from the ground plane of the pose.
  if (grid_.points.empty()) return PoseCheck::kValid;
  const BoxExtent box = BoxExtentAt(ground, vehicle);
  const double min_x = box.min_x_m, max_x = box.max_x_m, half_width = box.half_width_m, top = box.top_m;
  const double bottom = box.bottom_m;
  const bool all_points = vehicle.footprint_check == VehicleBox::FootprintCheck::kAllPoints;

  // Planar bounding box of the eight corners, in cells.
  const double lo_x = box.planar.min_x_m, hi_x = box.planar.max_x_m, lo_y = box.planar.min_y_m, hi_y = box.planar.max_y_m;
  const Grid& g = grid_;
  const int ix0 = std::max(0, static_cast<int>(std::floor((lo_x - g.origin_x_m) / g.cell_m)));
  const int ix1 = std::min(g.nx - 1, static_cast<int>(std::floor((hi_x - g.origin_x_m) / g.cell_m)));
  const int iy0 = std::max(0, static_cast<int>(std::floor((lo_y - g.origin_y_m) / g.cell_m)));
  const int iy1 = std::min(g.ny - 1, static_cast<int>(std::floor((hi_y - g.origin_y_m) / g.cell_m)));

  const Eigen::Matrix3d R_B_L = ground.T_L_B.linear().transpose();
  const Vec3 t_L = ground.T_L_B.translation();
  // Height band: a point's height in B is n . (p - t) with n the box's z axis in the map frame. Over a
  // cell, n_x (x - t_x) + n_y (y - t_y) lies in [h_lo, h_hi], so a point of the cell can be in the
  // band [ground clearance, top] only if its map-frame height lies in [z_lo, z_hi] below; the cell's points
  // are sorted by height, and only that run is tested. kWheels needs only what could collide, above
  // the ground clearance, which skips the ground; kAllPoints needs the whole slab down to `bottom`,
  // where the two binary searches per cell would cost more than they skip.
  const Vec3 n = R_B_L.row(2).transpose();
  const bool prune = !all_points && n.z() > 1e-3;
  constexpr double kSlackM = 1e-6;  // rounding of the cell bounds and of the transform
  bool ground_blocked = false;
  for (int iy = iy0; iy <= iy1; ++iy) {
    const double y0 = g.origin_y_m + iy * g.cell_m - kSlackM - t_L.y(), y1 = y0 + g.cell_m + 2.0 * kSlackM;
    const double hy_lo = std::min(n.y() * y0, n.y() * y1), hy_hi = std::max(n.y() * y0, n.y() * y1);
    for (int ix = ix0; ix <= ix1; ++ix) {
      const std::size_t cell =
          static_cast<std::size_t>(iy) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(ix);
      const Vec3* begin = g.points.data() + g.cell_begin[cell];
      const Vec3* end = g.points.data() + g.cell_begin[cell + 1];
      if (begin == end) continue;
      if (prune) {
        const double x0 = g.origin_x_m + ix * g.cell_m - kSlackM - t_L.x(), x1 = x0 + g.cell_m + 2.0 * kSlackM;
        const double h_lo = std::min(n.x() * x0, n.x() * x1) + hy_lo, h_hi = std::max(n.x() * x0, n.x() * x1) + hy_hi;
        const double z_lo = t_L.z() + (vehicle.ground_clearance_m - h_hi) / n.z() - kSlackM;
        const double z_hi = t_L.z() + (top - h_lo) / n.z() + kSlackM;
        begin = std::lower_bound(begin, end, z_lo, [](const Vec3& p, double z) { return p.z() < z; });
        end = std::upper_bound(begin, end, z_hi, [](double z, const Vec3& p) { return z < p.z(); });
      }
      for (const Vec3* it = begin; it != end; ++it) {
        const Vec3 p_B = R_B_L * (*it - t_L);
        if (p_B.x() < min_x || p_B.x() > max_x || std::abs(p_B.y()) > half_width || p_B.z() < bottom ||
            p_B.z() > top) {
          continue;
        }
        if (p_B.z() > vehicle.ground_clearance_m) return PoseCheck::kCollision;  // an obstacle, a roof, a wall in the box
        if (all_points && !g.traversable[static_cast<std::size_t>(it - g.points.data())]) ground_blocked = true;
      }
    }
  }
  // A collision anywhere in the box is reported before non-traversable ground under the footprint.
  if (ground_blocked) return PoseCheck::kGroundUnderFootprint;
  if (all_points) return PoseCheck::kValid;
  // Each wheel stands on known traversable ground: its contact point on the pose's ground plane is
  // close to a visible point, and that point is traversable.
  for (double x : {0.0, vehicle.wheelbase_m}) {
    for (double y : {-0.5 * vehicle.track_m, 0.5 * vehicle.track_m}) {
      const Vec3 contact = ground.T_L_B * Vec3(x, y, 0.0);
      if (InRegion(ground_.known_support, support_cos_, support_sin_, contact.x(), contact.y())) {
        // Where the vehicle stands; ahead of its front wheels (under the nose) seen steep ground
        // and the crest test still count.
        const SupportRegion& r = ground_.known_support;
        const double along = support_cos_ * (contact.x() - r.pose.x_m) + support_sin_ * (contact.y() - r.pose.y_m);
        if (!(along > r.crest_from_x_m)) continue;
        // Under the nose the vehicle does not stand: seen steep ground there (a ditch's wall just
        // below its lip) carries no wheel.
        const auto nearest = cloud_.Nearest(contact);
        if (nearest && nearest->distance_m <= vehicle.WheelSupportAt(contact.head<2>().norm()) &&
            !CarriesWheel(nearest->index)) {
          return PoseCheck::kGroundUnderFootprint;
        }
        if (vehicle.crest_margin_m >= 0.0 && OverUnseenDrop(ground, contact, vehicle)) return PoseCheck::kCrest;
        continue;
      }
      const auto nearest = cloud_.Nearest(contact);
      const double support_m = vehicle.WheelSupportAt(contact.head<2>().norm());
      if (!nearest || nearest->distance_m > support_m) {
        // Nothing seen near it now: ground seen there before, traversable and at the wheel's height
        // within a step, carries it (the crest test still applies).
        if (!ground_.remembered || !ground_.remembered->Carries(contact, support_m, vehicle.crest_step_m)) {
          return PoseCheck::kUnseenGround;
        }
      } else {
        if (!CarriesWheel(nearest->index)) return PoseCheck::kGroundUnderFootprint;
        if (nearest->distance_m > vehicle.edge_tolerance_m && !SeenBeyond(contact, vehicle.wheel_support_m)) {
          return PoseCheck::kUnseenGround;
        }
      }
      if (vehicle.crest_margin_m >= 0.0 && OverUnseenDrop(ground, contact, vehicle)) return PoseCheck::kCrest;
    }
  }
  return PoseCheck::kValid;
}

bool VertexCloudMap::CarriesWheel(int index) const {
  // A foot (a wall's, a post's) carries a wheel: what rises from it is the box test's, above the
  // ground clearance. A lip does not, nor a steep ramp's foot (not a foot: TraversabilityCloud::IsFoot).
  const auto i = static_cast<std::size_t>(index);
  return cloud_.traversable()[i] || cloud_.IsFoot(i);
}

bool VertexCloudMap::SeenBeyond(const Vec3& contact, double radius_m) const {
  // The viewpoint is the map frame's origin (the mapper's frame).
  const double reach = contact.head<2>().norm();
  for (const auto& n : cloud_.WithinRadius(contact, radius_m)) {
    if (cloud_.traversable()[n.index] && cloud_.points()[n.index].head<2>().norm() >= reach) return true;
  }
  return false;
}

template <class Visit>
bool VertexCloudMap::AnyInCells(double lo_x, double hi_x, double lo_y, double hi_y, double lo_z, double hi_z,
                                Visit&& visit) const {
  const Grid& g = grid_;
  const int ix0 = std::max(0, static_cast<int>(std::floor((lo_x - g.origin_x_m) / g.cell_m)));
  const int ix1 = std::min(g.nx - 1, static_cast<int>(std::floor((hi_x - g.origin_x_m) / g.cell_m)));
  const int iy0 = std::max(0, static_cast<int>(std::floor((lo_y - g.origin_y_m) / g.cell_m)));
  const int iy1 = std::min(g.ny - 1, static_cast<int>(std::floor((hi_y - g.origin_y_m) / g.cell_m)));
  for (int iy = iy0; iy <= iy1; ++iy) {
    for (int ix = ix0; ix <= ix1; ++ix) {
      const std::size_t cell = static_cast<std::size_t>(iy) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(ix);
      const Vec3* begin = g.points.data() + g.cell_begin[cell];
      const Vec3* end = g.points.data() + g.cell_begin[cell + 1];
      begin = std::lower_bound(begin, end, lo_z, [](const Vec3& p, double z) { return p.z() < z; });
      end = std::upper_bound(begin, end, hi_z, [](double z, const Vec3& p) { return z < p.z(); });
      for (const Vec3* it = begin; it != end; ++it) {
        if (visit(*it, g.traversable[static_cast<std::size_t>(it - g.points.data())] != 0)) return true;
      }
    }
  }
  return false;
}

bool VertexCloudMap::OverUnseenDrop(const GroundPose& ground, const Vec3& contact, const VehicleBox& vehicle) const {
  // Rays come from the viewpoint, the map frame's origin. The probe lies crest_margin_m beyond the
  // contact, away from the viewpoint, on the pose's ground plane.
  // How far beyond the probe a ray's end point may lie, and how far to the side of the probe's
  // vertical plane through the viewpoint: a ray past a lip meets the bottom or the far wall within
  // a few metres; the visible points lie a few centimetres to 0.5 m apart.
  constexpr double kRayReachM = 3.0;
  constexpr double kRayAsideM = 0.3;
  const double r_c = contact.head<2>().norm();
  if (!(r_c > 1e-6)) return false;
  const Vec3 n = ground.T_L_B.linear().col(2);
  const Vec3 out(contact.x() / r_c, contact.y() / r_c, 0.0);
  const Vec3 along = (out - out.dot(n) / n.z() * Vec3::UnitZ()).normalized();  // `out` tilted onto the plane
  const Vec3 p = contact + vehicle.crest_margin_m * along;
  const double r_p = p.head<2>().norm();
  if (!(r_p > 1e-6)) return false;
  const Vec3 u(p.x() / r_p, p.y() / r_p, 0.0);
  // (a) Seen traversable ground at or beyond the probe carries it: within wheel_support_m of it in
  // the plane, at least as far from the viewpoint, and within crest_step_m of its height plus what a
  // slope of max_tilt_deg rises or falls over the distance between them (a ramp below a crest).
  const double rho = vehicle.wheel_support_m;
  const double grade = std::tan(vehicle.max_tilt_deg * kPi / 180.0);
  const double band = vehicle.crest_step_m + grade * rho;
  const bool carried = AnyInCells(p.x() - rho, p.x() + rho, p.y() - rho, p.y() + rho, p.z() - band, p.z() + band,
                                  [&](const Vec3& q, bool traversable) {
                                    if (!traversable || q.head<2>().norm() < r_p) return false;
                                    // The footprint prior's ground, in the known support, was not seen.
                                    if (InRegion(ground_.known_support, support_cos_, support_sin_, q.x(), q.y())) return false;
                                    const double d2 = (q - p).head<2>().squaredNorm();
                                    return d2 <= rho * rho &&
                                           std::abs(q.z() - p.z()) <= vehicle.crest_step_m + grade * std::sqrt(d2);
                                  });
  if (carried) return false;  // the common case, and the cheaper search
  // (b) A ray that went under the probe: a visible point q beyond it (r_q in (r_p, r_p + reach], near
  // the vertical plane through the viewpoint and the probe) whose ray passes below z_p - drop at the
  // probe's range: z_q r_p / r_q < z_p - drop, i.e. z_q < (z_p - drop) r_q / r_p.
  const double below = p.z() - vehicle.crest_drop_m;
  const double z_hi = std::max(below, below * (r_p + kRayReachM) / r_p);
  const Vec3 far = p + kRayReachM * u;
  const bool ray_under = AnyInCells(
      std::min(p.x(), far.x()) - kRayAsideM, std::max(p.x(), far.x()) + kRayAsideM,
      std::min(p.y(), far.y()) - kRayAsideM, std::max(p.y(), far.y()) + kRayAsideM,
      -std::numeric_limits<double>::infinity(), z_hi, [&](const Vec3& q, bool) {
        const double r_q = q.head<2>().norm();
        if (!(r_q > r_p) || r_q > r_p + kRayReachM) return false;
        if (std::abs(u.x() * q.y() - u.y() * q.x()) > kRayAsideM) return false;
        return q.z() * r_p < below * r_q;
      });
  return ray_under;
}

bool VertexCloudMap::IsKnownFree(double x_m, double y_m) const {
  if (!bounds_.Contains(x_m, y_m)) return false;
  const auto ground = Project(Pose2{x_m, y_m, 0.0});
  return ground && ground->traversable;
}

}  // namespace ovpc::planner
