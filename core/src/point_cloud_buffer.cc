#include "ovpc/core/point_cloud_buffer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "internal_util.h"
#include "ovpc/core/internal/cell_table.h"

namespace ovpc {
namespace {

using internal::Mix;

bool IsFinite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

// Which of n indices Subsample keeps: the `max_points` with the smallest seeded hash. The hash is a
// bijection of the index, so no two indices tie and the kept set is exactly those with a hash at
// or below the max_points-th smallest.
class SubsampleThreshold {
 public:
  SubsampleThreshold(std::size_t n, std::size_t max_points, std::uint64_t seed) : salt_(Mix(seed)) {
    if (max_points == 0) {
      none_ = true;
      return;
    }
    thread_local std::vector<std::uint64_t> ranks;
    ranks.resize(n);
    for (std::size_t i = 0; i < n; ++i) ranks[i] = Rank(i);
    const auto nth = ranks.begin() + static_cast<std::ptrdiff_t>(max_points - 1);
    std::nth_element(ranks.begin(), nth, ranks.end());
    threshold_ = *nth;
  }
  bool operator()(std::size_t i) const { return !none_ && Rank(i) <= threshold_; }

 private:
  std::uint64_t Rank(std::size_t i) const { return Mix(salt_ ^ static_cast<std::uint64_t>(i)); }
  std::uint64_t salt_;
  std::uint64_t threshold_ = 0;
  bool none_ = false;
};

// Voxel hits accumulated in one pass: per voxel its key, the sum of its points and their count, in
// the order of each voxel's first point, found by key in a CellTable.
// `Key` is the integer type of the voxel indices: std::int32_t keeps the voxels small (and more of
// them in cache) when every index fits in it (see KeysFitInt32), std::int64_t works for any input.
template <typename Key>
class VoxelAccumulator {
 public:
  /// Points that AddBatch takes at once.
  static constexpr std::size_t kBatch = 16;

  /// Empties the accumulator for voxels of `voxel_size_m`; `max_points` bounds the points to come.
  void Reset(double voxel_size_m, std::size_t max_points) {
    inv_ = 1.0 / voxel_size_m;
    // Sized for the voxels of the previous use (the table grows when needed), at most for the
    // points: a smaller table stays in cache.
    table_.Reset(std::min(max_points, 3 * voxels_.size() / 2));
    voxels_.clear();
  }

  /// Adds up to kBatch points, in order: their slots are prefetched first, so that the cache
  /// misses of a batch overlap.
  void AddBatch(const Vec3* points, std::size_t n) {
    Key keys[kBatch][3];
    std::uint32_t hashes[kBatch];
    for (std::size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) keys[i][a] = static_cast<Key>(FloorToInt(points[i][a] * inv_));
      hashes[i] = internal::CellHash(keys[i]);
      table_.Prefetch(hashes[i]);
    }
    for (std::size_t i = 0; i < n; ++i) Add(keys[i], hashes[i], points[i]);
  }

  /// Appends the centroids of the voxels with at least `min_hits` points to `out`, in voxel order.
  void Extract(int min_hits, Points* out, BufferStats* stats) const {
    const auto min_count = static_cast<std::uint32_t>(min_hits);
    std::size_t kept = 0, sparse = 0;
    for (const Voxel& v : voxels_) {
      if (v.count >= min_count) {
        ++kept;
      } else {
        sparse += v.count;
      }
    }
    if (stats != nullptr) {
      stats->voxel_sparse += sparse;
      stats->voxels_kept += kept;
    }
    out->reserve(out->size() + kept);
    for (const Voxel& v : voxels_) {
      if (v.count >= min_count) out->push_back(v.sum / static_cast<double>(v.count));
    }
  }

 private:
  struct Voxel {
    Key key[3];
    std::uint32_t count;
    Vec3 sum;
  };
  // std::floor and a conversion, without the library call that std::floor is on baseline x86-64.
  static std::int64_t FloorToInt(double x) {
    const auto t = static_cast<std::int64_t>(x);
    return static_cast<double>(t) > x && t != std::numeric_limits<std::int64_t>::min() ? t - 1 : t;
  }

  void Add(const Key key[3], std::uint32_t hash, const Vec3& p) {
    bool inserted = false;
    const std::uint32_t id = table_.FindOrInsert(
        key, hash, [this](std::uint32_t v) { return voxels_[v].key; },
        [this] { return static_cast<std::uint32_t>(voxels_.size()); }, &inserted);
    if (inserted) {
      voxels_.push_back({{key[0], key[1], key[2]}, 1u, p});
    } else {
      Voxel& v = voxels_[id];
      v.sum += p;
      ++v.count;
    }
  }

  double inv_ = 1.0;
  internal::CellTable table_;
  std::vector<Voxel> voxels_;
};

// One accumulator of each kind per thread, reused so that its memory is allocated once.
template <typename Key>
VoxelAccumulator<Key>& ScratchVoxels() {
  thread_local VoxelAccumulator<Key> voxels;
  return voxels;
}

// Whether every voxel index of coordinates up to `max_abs` fits in an int32 (with a margin).
bool KeysFitInt32(double max_abs, double voxel_size_m) { return max_abs / voxel_size_m < 1e9; }

template <typename Key>
Points VoxelFilterWith(const Points& points, double voxel_size_m, int min_hits, BufferStats* stats) {
  constexpr std::size_t kBatch = VoxelAccumulator<Key>::kBatch;
  VoxelAccumulator<Key>& voxels = ScratchVoxels<Key>();
  voxels.Reset(voxel_size_m, points.size());
  for (std::size_t i = 0; i < points.size(); i += kBatch) voxels.AddBatch(&points[i], std::min(kBatch, points.size() - i));
  Points out;
  voxels.Extract(min_hits, &out, stats);
  return out;
}

}  // namespace

void PointCloudBuffer::Config::Validate() const {
  auto fail = [](const std::string& msg) { throw std::invalid_argument("PointCloudBuffer::Config: " + msg); };
  if (max_scans < 1) fail("max_scans must be >= 1, got " + std::to_string(max_scans));
  if (!(crop_radius_m > 0.0)) fail("crop_radius_m must be > 0, got " + std::to_string(crop_radius_m));
  if (!std::isfinite(voxel_size_m)) fail("voxel_size_m must be finite");
  if (min_hits < 1) fail("min_hits must be >= 1, got " + std::to_string(min_hits));
  if (!(near_range_m >= 0.0) || !std::isfinite(near_range_m)) {
    fail("near_range_m must be finite and >= 0, got " + std::to_string(near_range_m));
  }
  if (near_min_hits < 1) fail("near_min_hits must be >= 1, got " + std::to_string(near_min_hits));
  if (max_points < 4) fail("max_points must be >= 4, got " + std::to_string(max_points));
}

Points VoxelFilter(const Points& points, double voxel_size_m, int min_hits, BufferStats* stats) {
  if (!(voxel_size_m > 0.0)) return points;
  double max_abs = 0.0;
  for (const Vec3& p : points) max_abs = std::max(max_abs, p.cwiseAbs().maxCoeff());
  // Voxel keys are at most 64-bit: a coordinate of more voxels than that (1e30 m at 0.1 m) cannot be
  // converted; such points are dropped and counted as out of range, never all merged into one voxel.
  constexpr double kMaxVoxels = 4e18;
  if (max_abs / voxel_size_m >= kMaxVoxels) {
    Points in_range;
    in_range.reserve(points.size());
    for (const Vec3& p : points) {
      if (p.cwiseAbs().maxCoeff() / voxel_size_m < kMaxVoxels) {
        in_range.push_back(p);
      } else if (stats != nullptr) {
        ++stats->out_of_range;
      }
    }
    return VoxelFilter(in_range, voxel_size_m, min_hits, stats);
  }
  return KeysFitInt32(max_abs, voxel_size_m) ? VoxelFilterWith<std::int32_t>(points, voxel_size_m, min_hits, stats)
                                             : VoxelFilterWith<std::int64_t>(points, voxel_size_m, min_hits, stats);
}

Points Subsample(const Points& points, std::size_t max_points, std::uint64_t seed, BufferStats* stats) {
  if (points.size() <= max_points) return points;
  const SubsampleThreshold keep(points.size(), max_points, seed);
  Points out;
  out.reserve(max_points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (keep(i)) out.push_back(points[i]);
  }
  if (stats != nullptr) stats->subsampled_out += points.size() - max_points;
  return out;
}

// The voxels of the buffered scans, in a grid fixed in frame O. Voxels live in a vector (a freed one
// is reused) and a CellTable maps a voxel's index triple to it.
class PointCloudBuffer::Grid {
 public:
  static constexpr double kSteps = 1048576.0;  // 2^20 positions along a voxel edge
  // Voxel k spans [k - shift, k + 1 - shift) voxel edges along each axis of O. Vertically the grid is
  // shifted by half a voxel: O's origin is on the ground the vehicle starts on, and flat ground at
  // a voxel boundary would split into two layers of centroids (one each side, a noise's width apart).
  static constexpr double kShift[3] = {0.0, 0.0, 0.5};

  struct Voxel {
    std::int32_t key[3];
    std::uint32_t count;  // 0: free
    std::int64_t sum[3];  // of the points' positions in the voxel, in 1 / kSteps of its edge
  };

  explicit Grid(double voxel_size_m) : size_(voxel_size_m), inv_(1.0 / voxel_size_m) { table_.Reset(512); }

  /// Puts n <= kBatch points into their voxels at once: their slots are prefetched first, so that the cache misses
  /// overlap. ok[i] says whether point i was added.
  static constexpr std::size_t kBatch = 16;
  void AddBatch(const Vec3* p_O, std::size_t n, Entry* entries, bool* ok) {
    std::int32_t keys[kBatch][3];
    std::uint32_t hashes[kBatch];
    for (std::size_t i = 0; i < n; ++i) {
      ok[i] = Locate(p_O[i], keys[i], &entries[i]);
      hashes[i] = ok[i] ? internal::CellHash(keys[i]) : 0u;
      table_.Prefetch(hashes[i]);
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (ok[i]) Insert(keys[i], hashes[i], &entries[i]);
    }
  }

  /// Remove for n <= kBatch entries at once (their voxels prefetched first).
  void RemoveBatch(const Entry* entries, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) __builtin_prefetch(&voxels_[entries[i].voxel]);
    for (std::size_t i = 0; i < n; ++i) Remove(entries[i]);
  }

  void Remove(const Entry& e) {
    Voxel& v = voxels_[e.voxel];
    for (int a = 0; a < 3; ++a) v.sum[a] -= e.q[a];
    if (--v.count == 0) Free(e.voxel);
  }

  /// The centroid of a voxel's hits in frame O.
  Vec3 Centroid(const Voxel& v) const {
    const double n = static_cast<double>(v.count);
    Vec3 c;
    for (int a = 0; a < 3; ++a) {
      c[a] = size_ * (static_cast<double>(v.key[a]) - kShift[a] + (static_cast<double>(v.sum[a]) + 0.5 * n) / (n * kSteps));
    }
    return c;
  }

  const std::vector<Voxel>& voxels() const { return voxels_; }

 private:
  // The voxel index of p_O and its position in the voxel; false when an index is beyond int32.
  bool Locate(const Vec3& p_O, std::int32_t key[3], Entry* entry) const {
    for (int a = 0; a < 3; ++a) {
      const double f = p_O[a] * inv_ + kShift[a];
      if (!(f >= -2147483648.0 && f < 2147483648.0)) return false;
      auto t = static_cast<std::int64_t>(f);  // floor without a library call
      if (static_cast<double>(t) > f) --t;
      key[a] = static_cast<std::int32_t>(t);
      // f - t is exact (and in [0, 1)); the scaling by 2^20 too.
      entry->q[a] = std::min(static_cast<std::uint32_t>((f - static_cast<double>(t)) * kSteps),
                             static_cast<std::uint32_t>(kSteps) - 1);
    }
    return true;
  }

  void Insert(const std::int32_t key[3], std::uint32_t hash, Entry* entry) {
    const std::uint32_t id = FindOrInsert(key, hash);
    Voxel& v = voxels_[id];
    ++v.count;
    for (int a = 0; a < 3; ++a) v.sum[a] += entry->q[a];
    entry->voxel = id;
  }

  std::uint32_t FindOrInsert(const std::int32_t key[3], std::uint32_t hash) {
    bool inserted = false;
    const std::uint32_t id = table_.FindOrInsert(
        key, hash, [this](std::uint32_t v) { return voxels_[v].key; },
        [this] {
          if (free_.empty()) {
            voxels_.emplace_back();
            return static_cast<std::uint32_t>(voxels_.size() - 1);
          }
          const std::uint32_t reused = free_.back();
          free_.pop_back();
          return reused;
        },
        &inserted);
    if (inserted) voxels_[id] = Voxel{{key[0], key[1], key[2]}, 0u, {0, 0, 0}};
    return id;
  }

  void Free(std::uint32_t id) {
    table_.Erase(id, internal::CellHash(voxels_[id].key));
    free_.push_back(id);
  }

  double size_, inv_;
  std::vector<Voxel> voxels_;
  std::vector<std::uint32_t> free_;
  internal::CellTable table_;
};

PointCloudBuffer::PointCloudBuffer(const Config& config) : config_(config) {
  config_.Validate();
  if (config_.voxel_size_m > 0.0) grid_ = std::make_unique<Grid>(config_.voxel_size_m);
}

PointCloudBuffer::~PointCloudBuffer() = default;
PointCloudBuffer::PointCloudBuffer(PointCloudBuffer&&) noexcept = default;
PointCloudBuffer& PointCloudBuffer::operator=(PointCloudBuffer&&) noexcept = default;

void PointCloudBuffer::Clear() {
  scans_.clear();
  if (grid_) grid_ = std::make_unique<Grid>(config_.voxel_size_m);
}

void PointCloudBuffer::Push(Scan scan) {
  if (!scan.T_O_S.matrix().allFinite()) {
    throw std::invalid_argument("PointCloudBuffer::Push: scan pose is not finite");
  }
  // The oldest leaves first, so that its voxels are free for the new scan.
  while (scans_.size() >= static_cast<std::size_t>(config_.max_scans)) {
    if (grid_) {
      const std::vector<Entry>& entries = scans_.front().entries;
      for (std::size_t i = 0; i < entries.size(); i += Grid::kBatch) {
        grid_->RemoveBatch(&entries[i], std::min(Grid::kBatch, entries.size() - i));
      }
    }
    scans_.pop_front();
  }
  Stored stored;
  stored.T_O_S = scan.T_O_S;
  stored.time_s = scan.time_s;
  stored.input = scan.points_S.size();
  if (grid_) {
    stored.entries.reserve(scan.points_S.size());
    constexpr std::size_t kBatch = Grid::kBatch;
    Vec3 batch_O[kBatch];
    Entry entries[kBatch];
    bool ok[kBatch];
    std::size_t n = 0;
    const auto flush = [&] {
      grid_->AddBatch(batch_O, n, entries, ok);
      for (std::size_t i = 0; i < n; ++i) {
        if (ok[i]) {
          stored.entries.push_back(entries[i]);
        } else {
          ++stored.out_of_grid;
        }
      }
      n = 0;
    };
    for (const Vec3& p_S : scan.points_S) {
      if (!IsFinite(p_S)) {
        ++stored.non_finite;
        continue;
      }
      batch_O[n++] = scan.T_O_S * p_S;
      if (n == kBatch) flush();
    }
    if (n > 0) flush();
  } else {
    scan.points_S.erase(std::remove_if(scan.points_S.begin(), scan.points_S.end(),
                                       [](const Vec3& p) { return !IsFinite(p); }),
                        scan.points_S.end());
    stored.non_finite = stored.input - scan.points_S.size();
    stored.points_S = std::move(scan.points_S);
  }
  scans_.push_back(std::move(stored));
}

PointCloudBuffer::LocalCloud PointCloudBuffer::Build() const {
  LocalCloud result;
  if (scans_.empty()) return result;
  const Stored& newest = scans_.back();
  result.time_s = newest.time_s;
  // L: origin at the newest sensor position, axes of the gravity-aligned odometry frame.
  result.T_O_L = Eigen::Isometry3d::Identity();
  result.T_O_L.translation() = newest.T_O_S.translation();
  const Vec3 origin_O = newest.T_O_S.translation();
  const double r2 = config_.crop_radius_m * config_.crop_radius_m;

  BufferStats& stats = result.stats;
  std::size_t total = 0;
  for (const Stored& s : scans_) {
    total += s.points_S.size();
    stats.input += s.input;
    stats.non_finite += s.non_finite;
    stats.out_of_range += s.out_of_grid;
  }
  if (!grid_) {
    const Eigen::Isometry3d T_L_O = result.T_O_L.inverse();
    Points merged_L;
    merged_L.reserve(total);
    for (const Stored& s : scans_) {
      const Eigen::Isometry3d T_L_S = T_L_O * s.T_O_S;
      for (const Vec3& p_S : s.points_S) {
        const Vec3 p_L = T_L_S * p_S;
        if (p_L.squaredNorm() > r2) {
          ++stats.out_of_range;
          continue;
        }
        merged_L.push_back(p_L);
      }
    }
    result.points_L = Subsample(merged_L, config_.max_points, config_.seed, &stats);
    stats.output = result.points_L.size();
    return result;
  }

  // The voxels with enough hits within the crop radius, with the rank that subsampling keeps by.
  const auto far_count = static_cast<std::uint32_t>(config_.min_hits);
  const auto near_count = static_cast<std::uint32_t>(std::max(config_.min_hits, config_.near_min_hits));
  const double near2 = config_.near_range_m * config_.near_range_m;
  const std::uint64_t salt = Mix(config_.seed);
  thread_local Points kept_L;
  thread_local std::vector<std::uint64_t> ranks;
  kept_L.clear();
  ranks.clear();
  for (const Grid::Voxel& v : grid_->voxels()) {
    if (v.count < far_count) {  // free voxels have 0
      stats.voxel_sparse += v.count;
      continue;
    }
    const Vec3 p_L = grid_->Centroid(v) - origin_O;
    const double d2 = p_L.squaredNorm();
    if (d2 > r2) {
      stats.out_of_range += v.count;
      continue;
    }
    if (v.count < near_count && d2 < near2) {
      stats.voxel_sparse += v.count;
      continue;
    }
    kept_L.push_back(p_L);
    ranks.push_back(Mix(salt ^ internal::HashCellKey(v.key[0], v.key[1], v.key[2])));
  }
  stats.voxels_kept = kept_L.size();
  if (kept_L.size() <= config_.max_points) {
    result.points_L = kept_L;
  } else {
    // The max_points smallest ranks (64-bit hashes of the index triple: a tie is rare, and the count
    // bound holds even then).
    thread_local std::vector<std::uint64_t> sorted;
    sorted = ranks;
    const auto nth = sorted.begin() + static_cast<std::ptrdiff_t>(config_.max_points - 1);
    std::nth_element(sorted.begin(), nth, sorted.end());
    const std::uint64_t threshold = *nth;
    result.points_L.reserve(config_.max_points);
    for (std::size_t i = 0; i < kept_L.size() && result.points_L.size() < config_.max_points; ++i) {
      if (ranks[i] <= threshold) result.points_L.push_back(kept_L[i]);
    }
    stats.subsampled_out = kept_L.size() - result.points_L.size();
  }
  stats.output = result.points_L.size();
  return result;
}

}  // namespace ovpc
