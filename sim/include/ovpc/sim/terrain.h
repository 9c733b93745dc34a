// Generated terrain: a regular heightfield grid shared by the physics (a MuJoCo hfield) and the
// LiDAR (Embree triangles), so the vehicle drives on exactly the surface the sensor sees.
#pragma once

#include <cstdint>
#include <vector>

#include "ovpc/core/types.h"

namespace ovpc::sim {

/// What the ground looks like. Heights are in metres, in the world frame W (z up). The profile
/// kinds vary along one horizontal direction (`direction_deg`, counter-clockwise from +x); the
/// rough overlay is added to any kind.
struct TerrainConfig {
  enum class Kind {
    kFlat,   ///< z = 0
    kSlope,  ///< a plane through the origin rising along the direction
    kRamp,   ///< flat, then a planar ramp rising along the direction, then a plateau
    kDitch,  ///< flat with a trapezoidal ditch running across the direction
    kRough,  ///< flat with the fractal overlay (rough.amplitude_m must be > 0)
  };
  struct Slope {
    double angle_deg = 10.0;
  };
  struct Ramp {
    double start_m = 5.0;     ///< distance along the direction where the ramp starts
    double angle_deg = 20.0;  ///< ramp inclination
    double height_m = 1.0;    ///< plateau height
    /// A lane across which the ramp is gentler (a detour around a steep ramp): points whose
    /// distance across the direction is within lane_width_m / 2 of lane_centre_m rise at
    /// lane_angle_deg instead. 0 means no lane.
    double lane_angle_deg = 0.0;
    double lane_centre_m = 0.0;
    double lane_width_m = 6.0;
  };
  struct Ditch {
    double centre_m = 5.0;        ///< distance along the direction of the ditch's centre line
    double depth_m = 0.5;
    double bottom_width_m = 0.5;
    double wall_angle_deg = 45.0;  ///< inclination of the two walls
  };
  /// Fractal value noise: octaves of smoothly interpolated lattice noise, the first with
  /// wavelength `feature_m`, each next one half as long and `persistence` times as strong, down to
  /// two cells. Heights stay within +-amplitude_m; their standard deviation is about a quarter of it.
  struct Rough {
    double amplitude_m = 0.0;  ///< 0 disables the overlay
    double feature_m = 8.0;
    double persistence = 0.5;
    std::uint64_t seed = 1;
  };

  Kind kind = Kind::kFlat;
  /// Extent, centred on the origin; rounded up to whole cells.
  double size_x_m = 60.0;
  double size_y_m = 60.0;
  /// Grid spacing. Physics cost grows fast below 0.1 m; 0.2 m keeps physics + LiDAR within budget.
  double cell_m = 0.2;
  double direction_deg = 0.0;
  Slope slope;
  Ramp ramp;
  Ditch ditch;
  Rough rough;

  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

/// A regular grid of heights: rows along +y, columns along +x, vertex (r, c) at
/// (x_min_m + c cell_m, y_min_m + r cell_m). Each cell is split into two triangles along the
/// diagonal from vertex (r, c) to (r + 1, c + 1), the split MuJoCo's heightfield collision uses.
class Heightfield {
 public:
  Heightfield(int num_rows, int num_cols, double x_min_m, double y_min_m, double cell_m,
              std::vector<double> heights_m);

  int num_rows() const { return num_rows_; }
  int num_cols() const { return num_cols_; }
  double x_min_m() const { return x_min_m_; }
  double y_min_m() const { return y_min_m_; }
  double x_max_m() const { return x_min_m_ + (num_cols_ - 1) * cell_m_; }
  double y_max_m() const { return y_min_m_ + (num_rows_ - 1) * cell_m_; }
  double cell_m() const { return cell_m_; }
  double min_height_m() const { return min_height_m_; }
  double max_height_m() const { return max_height_m_; }
  double At(int row, int col) const { return heights_m_[static_cast<std::size_t>(row) * num_cols_ + col]; }
  const std::vector<double>& heights_m() const { return heights_m_; }
  Vec3 Vertex(int row, int col) const {
    return Vec3(x_min_m_ + col * cell_m_, y_min_m_ + row * cell_m_, At(row, col));
  }

  /// Height of the triangulated surface at (x, y); points outside the grid are clamped onto it.
  double HeightAt(double x_m, double y_m) const;
  /// Upward unit normal of the triangle under (x, y) (clamped like HeightAt).
  Vec3 NormalAt(double x_m, double y_m) const;
  /// A lower bound of the surface over the axis-aligned rectangle (clamped to the grid): the lowest
  /// vertex of the cells it touches.
  double MinHeightIn(double x0_m, double y0_m, double x1_m, double y1_m) const;

 private:
  int num_rows_;
  int num_cols_;
  double x_min_m_;
  double y_min_m_;
  double cell_m_;
  std::vector<double> heights_m_;
  double min_height_m_;
  double max_height_m_;
};

/// Samples the terrain on its grid. Deterministic from the config (the rough seed included).
/// @throws std::invalid_argument if the config is invalid.
Heightfield MakeHeightfield(const TerrainConfig& config);

/// The profile height of the kind alone (no rough overlay) at (x, y): the closed form the grid
/// samples, for tests and for placing things.
double ProfileHeight(const TerrainConfig& config, double x_m, double y_m);

}  // namespace ovpc::sim
