#include "ovpc/core/point_cloud_buffer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "internal_util.h"

namespace ovpc {
namespace {

using internal::Mix;

bool IsFinite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }


}  // namespace

void PointCloudBuffer::Config::Validate() const {
  auto fail = [](const std::string& msg) { throw std::invalid_argument("PointCloudBuffer::Config: " + msg); };
  if (max_scans < 1) fail("max_scans must be >= 1, got " + std::to_string(max_scans));
  if (!(crop_radius_m > 0.0)) fail("crop_radius_m must be > 0, got " + std::to_string(crop_radius_m));
  if (!std::isfinite(voxel_size_m)) fail("voxel_size_m must be finite");
  if (min_hits < 1) fail("min_hits must be >= 1, got " + std::to_string(min_hits));
  if (max_points < 4) fail("max_points must be >= 4, got " + std::to_string(max_points));
}

Points VoxelFilter(const Points& points, double voxel_size_m, int min_hits, BufferStats* stats) {
  if (!(voxel_size_m > 0.0)) return points;
  // One pass with an open-addressing hash table of voxels (sum, count), then the voxels in order of
  // their first point: O(n), deterministic, and no sort of the whole cloud.
  struct Voxel {
    std::int64_t key[3];
    Vec3 sum;
    std::uint32_t count;
    std::uint32_t first;  // index of the voxel's first point, for the output order
  };
  thread_local std::vector<Voxel> voxels;
  thread_local std::vector<std::int32_t> table;
  std::size_t capacity = 16;
  while (capacity < 2 * points.size()) capacity *= 2;
  table.assign(capacity, -1);
  voxels.clear();
  const double inv = 1.0 / voxel_size_m;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    const std::int64_t k[3] = {static_cast<std::int64_t>(std::floor(p.x() * inv)),
                               static_cast<std::int64_t>(std::floor(p.y() * inv)),
                               static_cast<std::int64_t>(std::floor(p.z() * inv))};
    std::uint64_t h = Mix(static_cast<std::uint64_t>(k[0]) * 0x9e3779b97f4a7c15ULL ^
                          static_cast<std::uint64_t>(k[1]) * 0xc2b2ae3d27d4eb4fULL ^
                          static_cast<std::uint64_t>(k[2]) * 0x165667b19e3779f9ULL);
    std::size_t slot = h & (capacity - 1);
    while (true) {
      const std::int32_t v = table[slot];
      if (v < 0) {
        table[slot] = static_cast<std::int32_t>(voxels.size());
        voxels.push_back({{k[0], k[1], k[2]}, p, 1u, static_cast<std::uint32_t>(i)});
        break;
      }
      Voxel& vox = voxels[v];
      if (vox.key[0] == k[0] && vox.key[1] == k[1] && vox.key[2] == k[2]) {
        vox.sum += p;
        ++vox.count;
        break;
      }
      slot = (slot + 1) & (capacity - 1);
    }
  }
  Points out;
  std::size_t sparse = 0;
  for (const Voxel& v : voxels) {
    if (v.count >= static_cast<std::uint32_t>(min_hits)) {
      out.push_back(v.sum / static_cast<double>(v.count));
    } else {
      sparse += v.count;
    }
  }
  if (stats != nullptr) {
    stats->voxel_sparse += sparse;
    stats->voxels_kept += out.size();
  }
  return out;
}

Points Subsample(const Points& points, std::size_t max_points, std::uint64_t seed, BufferStats* stats) {
  if (points.size() <= max_points) return points;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> ranked(points.size());
  const std::uint64_t salt = Mix(seed);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ranked[i] = {Mix(salt ^ static_cast<std::uint64_t>(i)), static_cast<std::uint32_t>(i)};
  }
  std::nth_element(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(max_points), ranked.end());
  ranked.resize(max_points);
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  Points out;
  out.reserve(max_points);
  for (const auto& r : ranked) out.push_back(points[r.second]);
  if (stats != nullptr) stats->subsampled_out += points.size() - max_points;
  return out;
}

PointCloudBuffer::PointCloudBuffer(const Config& config) : config_(config) { config_.Validate(); }

void PointCloudBuffer::Push(Scan scan) {
  if (!scan.T_O_S.matrix().allFinite()) {
    throw std::invalid_argument("PointCloudBuffer::Push: scan pose is not finite");
  }
  Stored stored;
  const std::size_t before = scan.points_S.size();
  scan.points_S.erase(std::remove_if(scan.points_S.begin(), scan.points_S.end(),
                                     [](const Vec3& p) { return !IsFinite(p); }),
                      scan.points_S.end());
  stored.non_finite = before - scan.points_S.size();
  stored.scan = std::move(scan);
  scans_.push_back(std::move(stored));
  while (scans_.size() > static_cast<std::size_t>(config_.max_scans)) scans_.pop_front();
}

PointCloudBuffer::LocalCloud PointCloudBuffer::Build() const {
  LocalCloud result;
  if (scans_.empty()) return result;
  const Scan& newest = scans_.back().scan;
  result.time_s = newest.time_s;
  // L: origin at the newest sensor position, axes of the gravity-aligned odometry frame.
  result.T_O_L = Eigen::Isometry3d::Identity();
  result.T_O_L.translation() = newest.T_O_S.translation();
  const Eigen::Isometry3d T_L_O = result.T_O_L.inverse();
  const double r2 = config_.crop_radius_m * config_.crop_radius_m;

  BufferStats& stats = result.stats;
  Points merged_L;
  std::size_t total = 0;
  for (const Stored& s : scans_) total += s.scan.points_S.size();
  merged_L.reserve(total);
  for (const Stored& s : scans_) {
    stats.input += s.scan.points_S.size() + s.non_finite;
    stats.non_finite += s.non_finite;
    const Eigen::Isometry3d T_L_S = T_L_O * s.scan.T_O_S;
    for (const Vec3& p_S : s.scan.points_S) {
      const Vec3 p_L = T_L_S * p_S;
      if (p_L.squaredNorm() > r2) {
        ++stats.out_of_range;
        continue;
      }
      merged_L.push_back(p_L);
    }
  }
  Points filtered = VoxelFilter(merged_L, config_.voxel_size_m, config_.min_hits, &stats);
  result.points_L = Subsample(filtered, config_.max_points, config_.seed, &stats);
  stats.output = result.points_L.size();
  return result;
}

}  // namespace ovpc
