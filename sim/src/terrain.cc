#include "ovpc/sim/terrain.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "random.h"

namespace ovpc::sim {
namespace {

// At most 4 million heightfield vertices (400 m x 400 m at the default 0.2 m cell): MuJoCo's and
// Embree's copies of the grid take about 120 bytes a vertex, so this bounds a world at about 0.5 GB.
constexpr double kMaxGridVertices = 4e6;

/// Uniform value in [-1, 1] at a lattice node of one octave.
double LatticeValue(std::uint64_t seed, int octave, std::int64_t ix, std::int64_t iy) {
  std::uint64_t h = HashCombine(seed, static_cast<std::uint64_t>(octave));
  h = HashCombine(h, static_cast<std::uint64_t>(ix));
  h = HashCombine(h, static_cast<std::uint64_t>(iy));
  return 2.0 * ToUnitInterval(h) - 1.0;
}

/// Quintic fade: C2-continuous interpolation weight.
double Fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

/// One octave of value noise in [-1, 1] at (x, y) for a lattice of spacing `wavelength_m`.
double ValueNoise(std::uint64_t seed, int octave, double wavelength_m, double x_m, double y_m) {
  const double gx = x_m / wavelength_m;
  const double gy = y_m / wavelength_m;
  const double fx = std::floor(gx);
  const double fy = std::floor(gy);
  const auto ix = static_cast<std::int64_t>(fx);
  const auto iy = static_cast<std::int64_t>(fy);
  const double u = Fade(gx - fx);
  const double v = Fade(gy - fy);
  const double v00 = LatticeValue(seed, octave, ix, iy);
  const double v10 = LatticeValue(seed, octave, ix + 1, iy);
  const double v01 = LatticeValue(seed, octave, ix, iy + 1);
  const double v11 = LatticeValue(seed, octave, ix + 1, iy + 1);
  const double bottom = v00 + u * (v10 - v00);
  const double top = v01 + u * (v11 - v01);
  return bottom + v * (top - bottom);
}

double RoughHeight(const TerrainConfig& config, double x_m, double y_m) {
  const TerrainConfig::Rough& rough = config.rough;
  if (rough.amplitude_m <= 0.0) return 0.0;
  double sum = 0.0;
  double weight_sum = 0.0;
  double weight = 1.0;
  double wavelength_m = rough.feature_m;
  for (int octave = 0; octave < 32 && wavelength_m >= 2.0 * config.cell_m; ++octave) {
    sum += weight * ValueNoise(rough.seed, octave, wavelength_m, x_m, y_m);
    weight_sum += weight;
    weight *= rough.persistence;
    wavelength_m *= 0.5;
  }
  return weight_sum > 0.0 ? rough.amplitude_m * sum / weight_sum : 0.0;
}

int GridCount(double size_m, double cell_m) {
  return static_cast<int>(std::ceil(size_m / cell_m - 1e-9)) + 1;
}

}  // namespace

void TerrainConfig::Validate() const {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("TerrainConfig: " + what);
  };
  require(cell_m > 0.0 && std::isfinite(cell_m), "cell_m must be > 0");
  require(size_x_m >= cell_m && std::isfinite(size_x_m), "size_x_m must be >= cell_m");
  require(size_y_m >= cell_m && std::isfinite(size_y_m), "size_y_m must be >= cell_m");
  // Counted in floating point: a size over a cell must not be converted to int before it is bounded.
  const auto count = [this](double size_m) { return std::ceil(size_m / cell_m - 1e-9) + 1.0; };
  require(count(size_x_m) * count(size_y_m) <= kMaxGridVertices,
          "size_x_m / cell_m * size_y_m / cell_m is too large (more than 4 million vertices, e.g. 400 m x 400 m "
          "at the 0.2 m cell)");
  require(std::isfinite(direction_deg), "direction_deg must be finite");
  switch (kind) {
    case Kind::kFlat:
      break;
    case Kind::kSlope:
      require(std::abs(slope.angle_deg) < 80.0, "slope.angle_deg must be within (-80, 80)");
      break;
    case Kind::kRamp:
      require(ramp.angle_deg > 0.0 && ramp.angle_deg < 80.0, "ramp.angle_deg must be in (0, 80)");
      require(ramp.lane_angle_deg >= 0.0 && ramp.lane_angle_deg < 80.0, "ramp.lane_angle_deg must be in [0, 80)");
      require(ramp.lane_width_m > 0.0, "ramp.lane_width_m must be > 0");
      require(ramp.height_m > 0.0 && std::isfinite(ramp.height_m), "ramp.height_m must be > 0");
      require(std::isfinite(ramp.start_m), "ramp.start_m must be finite");
      break;
    case Kind::kDitch:
      require(ditch.depth_m > 0.0 && std::isfinite(ditch.depth_m), "ditch.depth_m must be > 0");
      require(ditch.bottom_width_m >= 0.0 && std::isfinite(ditch.bottom_width_m),
              "ditch.bottom_width_m must be >= 0");
      require(ditch.wall_angle_deg > 0.0 && ditch.wall_angle_deg <= 89.0,
              "ditch.wall_angle_deg must be in (0, 89]");
      require(std::isfinite(ditch.centre_m), "ditch.centre_m must be finite");
      break;
    case Kind::kRough:
      require(rough.amplitude_m > 0.0, "rough.amplitude_m must be > 0 for the rough kind");
      break;
    default:
      require(false, "kind is not one of the listed kinds");
  }
  require(rough.amplitude_m >= 0.0 && std::isfinite(rough.amplitude_m),
          "rough.amplitude_m must be >= 0");
  require(rough.feature_m > 0.0 && std::isfinite(rough.feature_m), "rough.feature_m must be > 0");
  require(rough.persistence > 0.0 && rough.persistence <= 1.0,
          "rough.persistence must be in (0, 1]");
}

double ProfileHeight(const TerrainConfig& config, double x_m, double y_m) {
  const double dir_rad = DegToRad(config.direction_deg);
  const double s_m = x_m * std::cos(dir_rad) + y_m * std::sin(dir_rad);
  switch (config.kind) {
    case TerrainConfig::Kind::kSlope:
      return s_m * std::tan(DegToRad(config.slope.angle_deg));
    case TerrainConfig::Kind::kRamp: {
      const TerrainConfig::Ramp& ramp = config.ramp;
      const double across_m = -x_m * std::sin(dir_rad) + y_m * std::cos(dir_rad);
      const bool in_lane = ramp.lane_angle_deg > 0.0 && std::abs(across_m - ramp.lane_centre_m) <= 0.5 * ramp.lane_width_m;
      const double angle_deg = in_lane ? ramp.lane_angle_deg : ramp.angle_deg;
      const double rise_m = (s_m - ramp.start_m) * std::tan(DegToRad(angle_deg));
      return std::clamp(rise_m, 0.0, config.ramp.height_m);
    }
    case TerrainConfig::Kind::kDitch: {
      const TerrainConfig::Ditch& d = config.ditch;
      const double tan_wall = std::tan(DegToRad(d.wall_angle_deg));
      const double half_top_m = 0.5 * d.bottom_width_m + d.depth_m / tan_wall;
      const double inside_m = half_top_m - std::abs(s_m - d.centre_m);
      return -std::clamp(inside_m * tan_wall, 0.0, d.depth_m);
    }
    case TerrainConfig::Kind::kFlat:
    case TerrainConfig::Kind::kRough:
    default:
      return 0.0;
  }
}

Heightfield MakeHeightfield(const TerrainConfig& config) {
  config.Validate();
  const int num_cols = GridCount(config.size_x_m, config.cell_m);
  const int num_rows = GridCount(config.size_y_m, config.cell_m);
  const double x_min_m = -0.5 * (num_cols - 1) * config.cell_m;
  const double y_min_m = -0.5 * (num_rows - 1) * config.cell_m;
  std::vector<double> heights(static_cast<std::size_t>(num_rows) * num_cols);
  for (int r = 0; r < num_rows; ++r) {
    const double y_m = y_min_m + r * config.cell_m;
    for (int c = 0; c < num_cols; ++c) {
      const double x_m = x_min_m + c * config.cell_m;
      heights[static_cast<std::size_t>(r) * num_cols + c] =
          ProfileHeight(config, x_m, y_m) + RoughHeight(config, x_m, y_m);
    }
  }
  return Heightfield(num_rows, num_cols, x_min_m, y_min_m, config.cell_m, std::move(heights));
}

Heightfield::Heightfield(int num_rows, int num_cols, double x_min_m, double y_min_m,
                         double cell_m, std::vector<double> heights_m)
    : num_rows_(num_rows),
      num_cols_(num_cols),
      x_min_m_(x_min_m),
      y_min_m_(y_min_m),
      cell_m_(cell_m),
      heights_m_(std::move(heights_m)) {
  if (num_rows_ < 2 || num_cols_ < 2) {
    throw std::invalid_argument("Heightfield: needs at least 2 rows and 2 columns");
  }
  if (!(cell_m_ > 0.0)) throw std::invalid_argument("Heightfield: cell_m must be > 0");
  if (heights_m_.size() != static_cast<std::size_t>(num_rows_) * num_cols_) {
    throw std::invalid_argument("Heightfield: heights size is not rows x cols");
  }
  for (const double h : heights_m_) {
    if (!std::isfinite(h)) throw std::invalid_argument("Heightfield: non-finite height");
  }
  const auto [lo, hi] = std::minmax_element(heights_m_.begin(), heights_m_.end());
  min_height_m_ = *lo;
  max_height_m_ = *hi;
}

namespace {

/// Cell index and the local coordinate within it, clamped onto the grid.
std::pair<int, double> Locate(double value_m, double min_m, double cell_m, int count) {
  const double g = std::clamp((value_m - min_m) / cell_m, 0.0, static_cast<double>(count - 1));
  const int i = std::min(static_cast<int>(g), count - 2);
  return {i, g - i};
}

}  // namespace

double Heightfield::HeightAt(double x_m, double y_m) const {
  const auto [c, u] = Locate(x_m, x_min_m_, cell_m_, num_cols_);
  const auto [r, v] = Locate(y_m, y_min_m_, cell_m_, num_rows_);
  const double h_a = At(r, c);
  const double h_b = At(r, c + 1);
  const double h_c = At(r + 1, c);
  const double h_d = At(r + 1, c + 1);
  if (v >= u) return h_a + u * (h_d - h_c) + v * (h_c - h_a);
  return h_a + u * (h_b - h_a) + v * (h_d - h_b);
}

Vec3 Heightfield::NormalAt(double x_m, double y_m) const {
  const auto [c, u] = Locate(x_m, x_min_m_, cell_m_, num_cols_);
  const auto [r, v] = Locate(y_m, y_min_m_, cell_m_, num_rows_);
  const double h_a = At(r, c);
  const double h_b = At(r, c + 1);
  const double h_c = At(r + 1, c);
  const double h_d = At(r + 1, c + 1);
  const double dhdx = (v >= u ? h_d - h_c : h_b - h_a) / cell_m_;
  const double dhdy = (v >= u ? h_c - h_a : h_d - h_b) / cell_m_;
  return Vec3(-dhdx, -dhdy, 1.0).normalized();
}

double Heightfield::MinHeightIn(double x0_m, double y0_m, double x1_m, double y1_m) const {
  const int c0 = Locate(std::min(x0_m, x1_m), x_min_m_, cell_m_, num_cols_).first;
  const int c1 = Locate(std::max(x0_m, x1_m), x_min_m_, cell_m_, num_cols_).first;
  const int r0 = Locate(std::min(y0_m, y1_m), y_min_m_, cell_m_, num_rows_).first;
  const int r1 = Locate(std::max(y0_m, y1_m), y_min_m_, cell_m_, num_rows_).first;
  double lowest_m = At(r0, c0);
  for (int r = r0; r <= r1 + 1; ++r) {
    for (int c = c0; c <= c1 + 1; ++c) lowest_m = std::min(lowest_m, At(r, c));
  }
  return lowest_m;
}

}  // namespace ovpc::sim
