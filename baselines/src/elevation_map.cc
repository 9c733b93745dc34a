#include "ovpc/baselines/elevation_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace ovpc::baselines {
namespace {

/// Cells per side above which a map is refused (about 7 GB): a guard against a unit slip.
constexpr double kMaxCellsPerSide = 25000.0;

void Require(bool ok, const char* field, const char* what) {
  if (!ok) {
    throw std::invalid_argument(std::string("ElevationMap::Config::") + field + " " + what);
  }
}

}  // namespace

void ElevationMap::Config::Validate() const {
  Require(resolution_m > 0.0 && std::isfinite(resolution_m), "resolution_m",
          "must be finite and > 0");
  Require(length_m >= resolution_m && std::isfinite(length_m), "length_m",
          "must be finite and >= resolution_m");
  Require(length_m / resolution_m <= kMaxCellsPerSide, "length_m",
          "gives more than 25000 cells per side");
  Require(mahalanobis_threshold > 0.0 && std::isfinite(mahalanobis_threshold),
          "mahalanobis_threshold", "must be finite and > 0");
  Require(sensor_sigma_m > 0.0 && std::isfinite(sensor_sigma_m), "sensor_sigma_m",
          "must be finite and > 0");
  Require(sensor_sigma_per_m >= 0.0 && std::isfinite(sensor_sigma_per_m), "sensor_sigma_per_m",
          "must be finite and >= 0");
  Require(!std::isnan(min_height_above_base_m) && !std::isnan(max_height_above_base_m) &&
              min_height_above_base_m < max_height_above_base_m,
          "min_height_above_base_m", "must be below max_height_above_base_m");
}

ElevationMap::ElevationMap(const Config& config) : config_(config) {
  config_.Validate();
  cells_ = static_cast<int>(std::lround(config_.length_m / config_.resolution_m));
  if (cells_ < 1) cells_ = 1;
  origin_col_ = -cells_ / 2;
  origin_row_ = -cells_ / 2;
  cells_data_.assign(static_cast<std::size_t>(cells_) * static_cast<std::size_t>(cells_), Cell{});
}

double ElevationMap::MeasurementVariance(double range_m) const {
  const double sigma_m = config_.sensor_sigma_m + config_.sensor_sigma_per_m * std::abs(range_m);
  return sigma_m * sigma_m;
}

Eigen::Vector2d ElevationMap::centre() const {
  const double half = 0.5 * cells_;
  return Eigen::Vector2d((static_cast<double>(origin_col_) + half) * config_.resolution_m,
                         (static_cast<double>(origin_row_) + half) * config_.resolution_m);
}

std::ptrdiff_t ElevationMap::IndexOf(double x, double y) const {
  if (!std::isfinite(x) || !std::isfinite(y)) return -1;
  const double col_f = std::floor(x / config_.resolution_m) - static_cast<double>(origin_col_);
  const double row_f = std::floor(y / config_.resolution_m) - static_cast<double>(origin_row_);
  if (col_f < 0.0 || row_f < 0.0 || col_f >= cells_ || row_f >= cells_) return -1;
  return static_cast<std::ptrdiff_t>(row_f) * cells_ + static_cast<std::ptrdiff_t>(col_f);
}

ElevationMap::UpdateStats ElevationMap::Update(const Points& points, const Vec3& sensor_position,
                                               double base_height_m) {
  if (!sensor_position.allFinite()) {
    throw std::invalid_argument("ElevationMap::Update: the sensor position is not finite");
  }
  if (!std::isfinite(base_height_m)) {
    throw std::invalid_argument("ElevationMap::Update: the base height is not finite");
  }
  UpdateStats stats;
  stats.input = points.size();
  const double min_z = base_height_m + config_.min_height_above_base_m;
  const double max_z = base_height_m + config_.max_height_above_base_m;
  const double gate2 = config_.mahalanobis_threshold * config_.mahalanobis_threshold;
  for (const Vec3& p : points) {
    if (!p.allFinite()) {
      ++stats.non_finite;
      continue;
    }
    const double z = p.z();
    if (z < min_z || z > max_z) {
      ++stats.cropped;
      continue;
    }
    const std::ptrdiff_t index = IndexOf(p.x(), p.y());
    if (index < 0) {
      ++stats.outside_map;
      continue;
    }
    Cell& cell = cells_data_[static_cast<std::size_t>(index)];
    const double r = MeasurementVariance((p - sensor_position).norm());
    if (cell.empty()) {
      cell.height_m = static_cast<float>(z);
      cell.variance_m2 = static_cast<float>(r);
      cell.measurements = 1;
      ++stats.initialised;
      continue;
    }
    const double h = cell.height_m;
    const double var = cell.variance_m2;
    const double innovation = z - h;
    if (innovation * innovation <= gate2 * (var + r)) {
      cell.height_m = static_cast<float>((r * h + var * z) / (var + r));
      cell.variance_m2 = static_cast<float>(var * r / (var + r));
      ++cell.measurements;
      ++stats.fused;
    } else if (innovation > 0.0) {
      cell.height_m = static_cast<float>(z);
      cell.variance_m2 = static_cast<float>(r);
      ++cell.measurements;
      ++stats.replaced;
    } else {
      ++stats.rejected;
    }
  }
  return stats;
}

void ElevationMap::Move(const Eigen::Vector2d& centre_xy) {
  if (!centre_xy.allFinite()) {
    throw std::invalid_argument("ElevationMap::Move: the centre is not finite");
  }
  const double half = 0.5 * cells_;
  const std::int64_t new_col = std::llround(centre_xy.x() / config_.resolution_m - half);
  const std::int64_t new_row = std::llround(centre_xy.y() / config_.resolution_m - half);
  if (new_col == origin_col_ && new_row == origin_row_) return;
  std::vector<Cell> moved(cells_data_.size(), Cell{});
  const std::int64_t shift_col = new_col - origin_col_;
  const std::int64_t shift_row = new_row - origin_row_;
  for (std::int64_t row = 0; row < cells_; ++row) {
    const std::int64_t old_row = row + shift_row;
    if (old_row < 0 || old_row >= cells_) continue;
    for (std::int64_t col = 0; col < cells_; ++col) {
      const std::int64_t old_col = col + shift_col;
      if (old_col < 0 || old_col >= cells_) continue;
      moved[static_cast<std::size_t>(row * cells_ + col)] =
          cells_data_[static_cast<std::size_t>(old_row * cells_ + old_col)];
    }
  }
  cells_data_ = std::move(moved);
  origin_col_ = new_col;
  origin_row_ = new_row;
}

void ElevationMap::Clear() { std::fill(cells_data_.begin(), cells_data_.end(), Cell{}); }

const ElevationMap::Cell* ElevationMap::FindCell(const Eigen::Vector2d& xy) const {
  const std::ptrdiff_t index = IndexOf(xy.x(), xy.y());
  return index < 0 ? nullptr : &cells_data_[static_cast<std::size_t>(index)];
}

std::optional<double> ElevationMap::HeightAt(const Eigen::Vector2d& xy) const {
  const Cell* cell = FindCell(xy);
  if (cell == nullptr || cell->empty()) return std::nullopt;
  return static_cast<double>(cell->height_m);
}

std::optional<double> ElevationMap::VarianceAt(const Eigen::Vector2d& xy) const {
  const Cell* cell = FindCell(xy);
  if (cell == nullptr || cell->empty()) return std::nullopt;
  return static_cast<double>(cell->variance_m2);
}

std::size_t ElevationMap::num_nonempty() const {
  std::size_t n = 0;
  for (const Cell& cell : cells_data_) n += cell.empty() ? 0 : 1;
  return n;
}

}  // namespace ovpc::baselines
