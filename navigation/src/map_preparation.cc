#include "ovpc/navigation/map_preparation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ovpc/core/internal/cell_table.h"

namespace ovpc::navigation {

void MapPreparation::Config::Validate() const {
  const auto fail = [](const std::string& m) { throw std::invalid_argument(m); };
  if (!(footprint_prior_margin_m >= 0.0) || footprint_prior_margin_m > 5.0) {
    fail("preparation.footprint_prior_margin_m must be in [0, 5]");
  }
  if (!(footprint_prior_blend_m >= 0.0) || footprint_prior_blend_m > 5.0) {
    fail("preparation.footprint_prior_blend_m must be in [0, 5]");
  }
  if (!(footprint_grid_m >= 0.05) || footprint_grid_m > 2.0) fail("preparation.footprint_grid_m must be in [0.05, 2]");
  if (!(footprint_edge_band_m >= 0.0) || footprint_edge_band_m > 2.0) {
    fail("preparation.footprint_edge_band_m must be in [0, 2]");
  }
  if (!(body_margin_m >= 0.0) || body_margin_m > 2.0) fail("preparation.body_margin_m must be in [0, 2]");
  if (!(isolated_point_radius_m >= 0.0) || isolated_point_radius_m > 2.0) {
    fail("preparation.isolated_point_radius_m must be in [0, 2]");
  }
  if (!(isolated_point_reach_m >= 0.0) || !std::isfinite(isolated_point_reach_m)) {
    fail("preparation.isolated_point_reach_m must be >= 0");
  }
}

namespace {

// The points of a cloud by cell of a cubic grid: a CellTable from a cell's integer key to its run
// of point indices (increasing) in one array. Built once per call, no allocation per cell.
class CellIndex {
 public:
  using Key = std::array<std::int64_t, 3>;

 private:
  // The table's view of the stored keys.
  auto KeyOfCell() const {
    return [this](std::uint32_t c) { return keys_[c].data(); };
  }

 public:
  CellIndex(double cell_m) : inv_(1.0 / cell_m) {}

  // The cell of `p`. Keys are clamped to +-2^62: a clamp is monotone and moves neighbouring keys
  // at most as far apart as they were, so two points within one cell edge stay in neighbouring
  // cells (and a coordinate that overflows an int64 cannot occur).
  Key KeyOf(const Vec3& p) const {
    constexpr double kMax = 4.0e18;
    Key k;
    for (int a = 0; a < 3; ++a) {
      const double c = std::floor(p[a] * inv_);
      k[a] = static_cast<std::int64_t>(c >= kMax ? kMax : (c <= -kMax ? -kMax : c));
    }
    return k;
  }

  // Indexes the points `indices` of `points` (in that order).
  void Build(const Points& points, const std::vector<std::uint32_t>& indices) {
    table_.Reset(indices.size());
    keys_.clear();
    std::vector<std::uint32_t> cell_of(indices.size());
    std::vector<std::uint32_t> count;
    for (std::size_t n = 0; n < indices.size(); ++n) {
      const Key k = KeyOf(points[indices[n]]);
      const std::uint32_t c = table_.FindOrInsert(k.data(), ovpc::internal::CellHash(k.data()), KeyOfCell(), [&] {
        keys_.push_back(k);
        count.push_back(0);
        return static_cast<std::uint32_t>(keys_.size() - 1);
      });
      cell_of[n] = c;
      ++count[c];
    }
    start_.assign(keys_.size() + 1, 0);
    for (std::size_t c = 0; c < keys_.size(); ++c) start_[c + 1] = start_[c] + count[c];
    members_.resize(indices.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t n = 0; n < indices.size(); ++n) members_[fill[cell_of[n]]++] = indices[n];
  }

  // The point indices in the cell `k` as [begin, end) of members(); empty if the cell is.
  std::pair<const std::uint32_t*, const std::uint32_t*> Cell(const Key& k) const {
    const std::optional<std::uint32_t> c = table_.Find(k.data(), ovpc::internal::CellHash(k.data()), KeyOfCell());
    if (!c) return {nullptr, nullptr};
    return {members_.data() + start_[*c], members_.data() + start_[*c + 1]};
  }

 private:
  double inv_;
  ovpc::internal::CellTable table_;
  std::vector<Key> keys_;
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> members_;
};

}  // namespace

void DropIsolatedPoints(double radius_m, double reach_m, Points* points_L) {
  if (!(radius_m > 0.0) || points_L->empty()) return;
  const Points& points = *points_L;
  const double r2 = radius_m * radius_m, reach2 = reach_m * reach_m;
  // Only points within reach_m + radius_m can be the neighbour of one within reach_m.
  const double indexed2 = (reach_m + radius_m) * (reach_m + radius_m);
  std::vector<std::uint32_t> indexed;
  indexed.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].squaredNorm() <= indexed2) indexed.push_back(static_cast<std::uint32_t>(i));
  }
  CellIndex cells(radius_m);
  cells.Build(points, indexed);
  std::vector<char> drop(points.size(), 0);
  for (std::uint32_t i : indexed) {
    const Vec3& p = points[i];
    if (p.squaredNorm() > reach2) continue;
    const CellIndex::Key k = cells.KeyOf(p);
    const auto has_neighbour_in = [&](const CellIndex::Key& cell) {
      const auto [begin, end] = cells.Cell(cell);
      for (const std::uint32_t* j = begin; j != end; ++j) {
        if (*j != i && (points[*j] - p).squaredNorm() <= r2) return true;
      }
      return false;
    };
    // The point's own cell first: most points have a neighbour there.
    bool neighbour = has_neighbour_in(k);
    for (int dx = -1; dx <= 1 && !neighbour; ++dx) {
      for (int dy = -1; dy <= 1 && !neighbour; ++dy) {
        for (int dz = -1; dz <= 1 && !neighbour; ++dz) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          neighbour = has_neighbour_in({k[0] + dx, k[1] + dy, k[2] + dz});
        }
      }
    }
    drop[i] = neighbour ? 0 : 1;
  }
  std::size_t out = 0;
  for (std::size_t i = 0; i < points_L->size(); ++i) {
    if (!drop[i]) (*points_L)[out++] = (*points_L)[i];
  }
  points_L->resize(out);
}

// Measured points inside the vehicle's box (the body grown by the body margin, up to its top) are
// dropped: returns off the vehicle itself on a real robot, outliers in simulation. A grid on the
// footprint plane (z = 0 in B), over the footprint grown by the prior's margin, stands for the
// ground. Low points (below the ground band in B), measured ground: with kReplace they are dropped
// over the grown footprint plus the edge band and the grid is laid everywhere (mixing measured
// ground with the grid would put noisy points a few centimetres from exact ones and make steep
// slivers of faces); with kFill they stay, and a grid point is laid only where no low point lies
// within the grid's spacing, so that a measured ramp ahead of the bumper is not cut off by the flat
// grid, optionally blended to the measured height (Config::footprint_prior_blend_m).
void AddFootprintPrior(const Eigen::Isometry3d& T_L_B, const FootprintBox& box, const MapPreparation::Config& config,
                       Points* points_L) {
  const double x0 = box.min_x_m, x1 = box.max_x_m;
  const double y0 = -box.half_width_m, y1 = box.half_width_m;
  const double margin_m = config.footprint_prior_margin_m, blend_m = config.footprint_prior_blend_m;
  const double ground_band_m = box.ground_band_m, top_m = box.top_m, body_margin_m = box.body_margin_m;
  const bool fill = config.footprint_prior_mode == MapPreparation::PriorMode::kFill;
  const double kStep = config.footprint_grid_m;
  const double reach = std::max(kStep, blend_m);
  const double g = margin_m + config.footprint_edge_band_m;
  const double grid_x1 = std::min(x1 + margin_m, box.ground_max_x_m);  // the grid's front end
  const Eigen::Isometry3d T_B_L = T_L_B.inverse();
  std::vector<Vec3> low_B;  // kFill: measured ground near the grid, in B
  points_L->erase(std::remove_if(points_L->begin(), points_L->end(),
                                 [&](const Vec3& p_L) {
                                   const Vec3 p = T_B_L * p_L;
                                   if (p.z() >= top_m) return false;
                                   const bool low = p.z() < ground_band_m;
                                   if (low && fill) {
                                     if (p.x() >= x0 - margin_m - reach && p.x() <= grid_x1 + reach &&
                                         p.y() >= y0 - margin_m - reach && p.y() <= y1 + margin_m + reach) {
                                       low_B.push_back(p);
                                     }
                                     return false;
                                   }
                                   const double m = low ? g : body_margin_m;
                                   const double front = low ? grid_x1 + config.footprint_edge_band_m : x1 + m;
                                   return p.x() >= x0 - m && p.x() <= front && p.y() >= y0 - m && p.y() <= y1 + m;
                                 }),
                  points_L->end());
  for (double x = x0 - margin_m; x <= grid_x1 + 1e-9; x += kStep) {
    for (double y = y0 - margin_m; y <= y1 + margin_m + 1e-9; y += kStep) {
      // Nearest measured ground and, when blending, the inverse-distance mean height of that within
      // `reach`.
      double nearest_sq = std::numeric_limits<double>::infinity(), weight_sum = 0.0, z_sum = 0.0;
      for (const Vec3& p : low_B) {
        const double d_sq = (p.x() - x) * (p.x() - x) + (p.y() - y) * (p.y() - y);
        nearest_sq = std::min(nearest_sq, d_sq);
        if (blend_m > 0.0 && d_sq < reach * reach) {
          const double w = 1.0 / (std::sqrt(d_sq) + 0.05);
          weight_sum += w;
          z_sum += w * p.z();
        }
      }
      if (fill && nearest_sq < kStep * kStep) continue;  // measured ground right here
      double z = 0.0;
      if (fill && blend_m > 0.0 && weight_sum > 0.0) z = (1.0 - std::sqrt(nearest_sq) / reach) * z_sum / weight_sum;
      points_L->push_back(T_L_B * Vec3(x, y, z));
    }
  }
}

}  // namespace ovpc::navigation
