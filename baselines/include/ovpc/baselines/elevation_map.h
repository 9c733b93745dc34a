// The project's 2.5D elevation-map baseline: a robot-centric height grid with per-cell Kalman
// height fusion and Mahalanobis gating, after the method of Fankhauser et al. ("Robot-centric
// elevation mapping with uncertainty estimates", CLAWAR 2014; "Probabilistic terrain mapping for
// mobile robots with uncertain localization", RA-L 2018). It is this project's own implementation
// of the published method, written for the runtime comparison and the closed-loop comparisons;
// it is not ANYbotics' elevation_mapping software and shares no code with it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "ovpc/core/types.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::baselines {

/// A square height grid that moves with the robot. Every cell holds the Kalman estimate of the
/// terrain height (mean and variance) fused from the points that fell into it.
///
/// Measurement update of one point p (range d from the sensor) in cell c:
///  - the point is dropped when its height above the robot base is outside
///    [min_height_above_base_m, max_height_above_base_m] (the height crop);
///  - its height variance is R = (sensor_sigma_m + sensor_sigma_per_m * d)^2;
///  - an empty cell takes (p.z, R);
///  - otherwise the Mahalanobis distance of the innovation, |p.z - h| / sqrt(P + R), decides:
///    within `mahalanobis_threshold` the height is fused (h <- (R h + P z) / (P + R),
///    P <- P R / (P + R)); beyond it a *higher* point replaces the cell (h <- z, P <- R: something
///    was put on top of the surface, or the old estimate was the lower side of a wall), and a
///    *lower* point is rejected (the lower side of a step seen through the cell, or an outlier),
///    leaving the cell unchanged.
///
/// Overhangs: a 2.5D map keeps one height per cell. With the default crop every point below
/// `max_height_above_base_m` counts, so a roof over the robot (higher than the ground by far more
/// than the gate) replaces the ground under it: the cells under a carport read as the roof's
/// height, i.e. an obstacle, and the ground there is lost. Lowering the crop below the roof drops
/// the roof and maps the ground, and then the roof is absent from the map. Neither sees both; that
/// is the limitation the paper shows (tests: ElevationMapTest.RoofAbove*).
///
/// Gating uses the innovation variance P + R (the Mahalanobis distance of the measurement against
/// the predicted measurement); gating on the cell variance P alone, as sometimes described, lets
/// the gate collapse as P shrinks with many fused points.
///
/// Not modelled: the prediction step that grows the variances with the robot's motion
/// uncertainty, the per-cell horizontal variances, the "fused" map that combines neighbouring
/// cells, visibility clean-up by ray casting, and derived layers (normals, traversability).
class ElevationMap {
 public:
  struct Config {
    double resolution_m = 0.1;   ///< cell edge length
    /// Side of the square map, centred on the robot. 50 m covers the point cloud buffer's 25 m
    /// crop radius, so the map sees the same points as the OVPC update (assumption).
    double length_m = 50.0;
    double mahalanobis_threshold = 2.5;  ///< gate on |z - h| / sqrt(P + R) (Fankhauser et al.)
    /// Height noise of one point: sigma = sensor_sigma_m + sensor_sigma_per_m * range.
    /// Assumption: 3 cm (VLP-16 range accuracy) plus 1.7 mm per metre (0.1 deg of angular error).
    double sensor_sigma_m = 0.03;
    double sensor_sigma_per_m = 0.0017;
    /// Height crop relative to the robot base (assumption: a 2.2 m tall vehicle and 0.8 m margin
    /// above; nothing cropped below).
    double min_height_above_base_m = -std::numeric_limits<double>::infinity();
    double max_height_above_base_m = 3.0;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, resolution_m), "m", "cell edge");
      v.Field(OVPC_FIELD(c, length_m), "m", "covers the buffer's 25 m crop radius");
      v.Field(OVPC_FIELD(c, mahalanobis_threshold), "", "gate on |z - h| / sqrt(P + R) (Fankhauser et al.)");
      v.Field(OVPC_FIELD(c, sensor_sigma_m), "m", "VLP-16 range accuracy (assumption)");
      v.Field(OVPC_FIELD(c, sensor_sigma_per_m), "m/m", "0.1 deg of angular error (assumption)");
      v.Field(OVPC_FIELD(c, min_height_above_base_m), "m", "nothing cropped below");
      v.Field(OVPC_FIELD(c, max_height_above_base_m), "m", "a roof below this is the height of the cells under it");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  struct Cell {
    float height_m = 0.0f;
    float variance_m2 = 0.0f;
    std::uint32_t measurements = 0;  ///< points that initialised, fused into or replaced the cell
    bool empty() const { return measurements == 0; }
  };

  /// What one Update() did with its points; every input point is counted exactly once.
  struct UpdateStats {
    std::size_t input = 0;
    std::size_t non_finite = 0;   ///< a coordinate was NaN or inf
    std::size_t cropped = 0;      ///< outside the height band above the robot base
    std::size_t outside_map = 0;  ///< beyond the map's extent
    std::size_t initialised = 0;  ///< first point of an empty cell
    std::size_t fused = 0;        ///< within the gate: Kalman update
    std::size_t replaced = 0;     ///< beyond the gate and higher: replaced the cell
    std::size_t rejected = 0;     ///< beyond the gate and lower: dropped
  };

  ElevationMap() : ElevationMap(Config{}) {}
  /// An empty map centred on the origin.
  /// @throws std::invalid_argument if the config is invalid.
  explicit ElevationMap(const Config& config);

  /// Fuses `points` (any frame whose z axis is gravity-up, the map's frame) measured from
  /// `sensor_position`; `base_height_m` is the z of the robot base in that frame (for the height
  /// crop). Never throws on bad points: they are counted.
  /// @throws std::invalid_argument if the sensor position or the base height is not finite.
  UpdateStats Update(const Points& points, const Vec3& sensor_position, double base_height_m);

  /// Re-centres the map on `centre_xy` (robot-centric), snapped to whole cells: cells keep their
  /// world position, cells that leave the map are dropped, cells that enter it are empty.
  /// @throws std::invalid_argument if the centre is not finite.
  void Move(const Eigen::Vector2d& centre_xy);

  /// Empties every cell (the map stays where it is).
  void Clear();

  /// The cell containing the world point (x, y), or nullptr outside the map.
  const Cell* FindCell(const Eigen::Vector2d& xy) const;
  /// Height / variance of the cell at (x, y), or nothing outside the map or in an empty cell.
  std::optional<double> HeightAt(const Eigen::Vector2d& xy) const;
  std::optional<double> VarianceAt(const Eigen::Vector2d& xy) const;

  /// Height variance R of a point measured at `range_m` from the sensor.
  double MeasurementVariance(double range_m) const;

  /// Centre of the map in the world (the last Move target, snapped to whole cells).
  Eigen::Vector2d centre() const;
  int cells_per_side() const { return cells_; }
  std::size_t num_nonempty() const;
  const Config& config() const { return config_; }

 private:
  /// Index of the cell containing (x, y), or -1 outside the map.
  std::ptrdiff_t IndexOf(double x, double y) const;

  Config config_;
  int cells_ = 0;
  /// Global index of the map's first column and row: global cell (i, j) covers
  /// [i, i + 1) x [j, j + 1) times the resolution, so cells keep their place when the map moves.
  std::int64_t origin_col_ = 0;
  std::int64_t origin_row_ = 0;
  /// Row-major: index = row * cells_ + col, col along +x, row along +y, (0, 0) at the min corner.
  std::vector<Cell> cells_data_;
};

}  // namespace ovpc::baselines
