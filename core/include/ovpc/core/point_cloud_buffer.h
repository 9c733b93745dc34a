// The point cloud buffer: the first stage of the OVPC pipeline (paper, "Point cloud buffer").
// Aligns the last N scans by local odometry, voxel-filters (>= 2 hits per voxel), crops and
// subsamples them into one cloud centred on the current sensor position.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "ovpc/core/types.h"
#include "ovpc/core/config_fields.h"

namespace ovpc {

/// One LiDAR scan: points in the sensor frame S, and the pose of S in the gravity-aligned local
/// odometry frame O at the scan time.
struct Scan {
  Points points_S;
  Eigen::Isometry3d T_O_S = Eigen::Isometry3d::Identity();
  double time_s = 0.0;
};

/// Counters of what each filter removed; all counts are points.
struct BufferStats {
  std::size_t input = 0;          ///< points in the buffered scans
  std::size_t non_finite = 0;     ///< NaN/inf points dropped
  std::size_t out_of_range = 0;   ///< dropped by the crop radius
  std::size_t voxel_sparse = 0;   ///< dropped in voxels with fewer than min_hits points
  std::size_t voxels_kept = 0;    ///< voxels that passed the hit filter
  std::size_t subsampled_out = 0; ///< dropped to meet max_points
  std::size_t output = 0;         ///< points in the result
};

/// Voxel filter: one point (the centroid of its hits) per voxel that holds at least `min_hits`
/// points. Output order is deterministic (voxels in the order of their first point). `voxel_size_m
/// <= 0` returns the input unchanged. Non-finite points must have been removed before.
Points VoxelFilter(const Points& points, double voxel_size_m, int min_hits, BufferStats* stats = nullptr);

/// Deterministic subsampling to at most `max_points`: keeps the points with the smallest value of a
/// seeded hash of their index, so the kept set is spread uniformly over the input and does not depend
/// on the platform's random number generator. Relative order is preserved.
Points Subsample(const Points& points, std::size_t max_points, std::uint64_t seed,
                 BufferStats* stats = nullptr);

/// The voxel filter is incremental and anchored in the odometry frame O: each scan's points go into
/// the voxels of a grid fixed in O when the scan is pushed, and come out of them when the scan leaves
/// the buffer, so Build() reads the voxels instead of re-voxelising every buffered scan (and a ground
/// point does not change voxels as the vehicle moves). A point's position inside its voxel is kept
/// in 2^-20 of the voxel edge and summed in integers: the centroids depend only on the scans in the
/// buffer, never on the order they came and went in. The grid is shifted down by half a voxel, so the
/// ground at O's origin (where the vehicle started) lies mid-voxel, not on a boundary.
class PointCloudBuffer {
 public:
  struct Config {
    int max_scans = 25;           ///< scans kept (paper: 20-30)
    double crop_radius_m = 25.0;  ///< points farther from the current sensor are dropped
    double voxel_size_m = 0.1;    ///< voxel filter edge length; <= 0 disables the filter
    int min_hits = 2;             ///< voxels with fewer points are outliers (paper: 2)
    /// Voxels whose centroid is within near_range_m of the newest sensor position need
    /// near_min_hits points instead: rays crowd there, so a spurious return (dust, multipath)
    /// shares a voxel with another far more often than far out, while a real surface that close
    /// is hit tens of times. 0: min_hits everywhere (the paper's rule).
    double near_range_m = 0.0;
    int near_min_hits = 2;
    std::size_t max_points = 14000;  ///< subsampling target (paper: 6,000-14,000 result points)
    std::uint64_t seed = 1;       ///< seed of the subsampling hash (of the voxel's index in O)

    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, max_scans), "scans", "paper: 20-30");
      v.Field(OVPC_FIELD(c, crop_radius_m), "m", "points farther from the current sensor are dropped");
      v.Field(OVPC_FIELD(c, voxel_size_m), "m", "voxel filter edge; <= 0: no filter");
      v.Field(OVPC_FIELD(c, min_hits), "points", "paper: voxels with fewer hits are outliers");
      v.Field(OVPC_FIELD(c, near_range_m), "m", "within this of the sensor a voxel needs near_min_hits; 0: paper");
      v.Field(OVPC_FIELD(c, near_min_hits), "points", "stray returns crowd near the sensor");
      v.Field(OVPC_FIELD(c, max_points), "points", "paper: 6,000-14,000 result points");
      v.Field(OVPC_FIELD(c, seed), "", "the subsampling hash's seed");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// A merged cloud in the local frame L: origin at the newest sensor position, axes of the
  /// gravity-aligned odometry frame O (so z is up and the viewpoint is the origin).
  struct LocalCloud {
    Points points_L;
    Eigen::Isometry3d T_O_L = Eigen::Isometry3d::Identity();
    double time_s = 0.0;
    BufferStats stats;
  };

  PointCloudBuffer() : PointCloudBuffer(Config{}) {}
  /// @throws std::invalid_argument if the config is invalid.
  explicit PointCloudBuffer(const Config& config);

  /// Adds a scan (its points into the voxels), dropping the oldest beyond `max_scans`. Non-finite
  /// points are dropped (and counted in the next Build()).
  /// @throws std::invalid_argument if the pose is not finite.
  void Push(Scan scan);

  /// The buffered scans as one cloud in frame L: the centroid of every voxel with enough hits
  /// (min_hits; near_min_hits within near_range_m of the newest sensor position) within
  /// crop_radius_m of that position, subsampled to max_points by a seeded hash of the voxel's index
  /// (the same voxel is kept or dropped from one Build to the next). With the voxel filter off
  /// (voxel_size_m <= 0): every point within the crop radius, subsampled by a hash of its position in
  /// the merged cloud. Returns an empty cloud when no scan was pushed.
  LocalCloud Build() const;

  std::size_t num_scans() const { return scans_.size(); }
  void Clear();
  const Config& config() const { return config_; }

  ~PointCloudBuffer();
  PointCloudBuffer(PointCloudBuffer&&) noexcept;
  PointCloudBuffer& operator=(PointCloudBuffer&&) noexcept;
  PointCloudBuffer(const PointCloudBuffer&) = delete;
  PointCloudBuffer& operator=(const PointCloudBuffer&) = delete;

 private:
  class Grid;
  /// Where one point of a buffered scan went: its voxel and its position in the voxel.
  struct Entry {
    std::uint32_t voxel;
    std::uint32_t q[3];
  };
  struct Stored {
    Eigen::Isometry3d T_O_S = Eigen::Isometry3d::Identity();
    double time_s = 0.0;
    std::size_t input = 0;        ///< points given, finite or not
    std::size_t non_finite = 0;
    std::size_t out_of_grid = 0;  ///< beyond any voxel index of the grid (2^31 voxels from O's origin)
    std::vector<Entry> entries;   ///< voxel filter on
    Points points_S;              ///< voxel filter off
  };
  Config config_;
  std::deque<Stored> scans_;
  std::unique_ptr<Grid> grid_;
};

}  // namespace ovpc
