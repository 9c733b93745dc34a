#include "ovpc/core/point_cloud_buffer.h"

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>

#include <gtest/gtest.h>

#include "ovpc/synth/synthetic_scene.h"

namespace ovpc {
namespace {

Eigen::Isometry3d Pose(const Vec3& t, double yaw_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = t;
  T.linear() = Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  return T;
}

PointCloudBuffer::Config NoFilter() {
  PointCloudBuffer::Config c;
  c.voxel_size_m = 0.0;
  c.min_hits = 1;
  return c;
}

// Lexicographic order of the coordinates' bits: a canonical order for comparing sets of points.
void SortPoints(Points* points) {
  std::sort(points->begin(), points->end(), [](const Vec3& a, const Vec3& b) {
    return std::memcmp(a.data(), b.data(), sizeof(Vec3)) < 0;
  });
}

// References written for clarity, not speed: the voxel filter and subsampling as separate passes, and
// the buffer computed from scratch at every Build() (the real one is incremental). The fast code must
// match them bit for bit.
namespace reference {

std::uint64_t Mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

Points VoxelFilter(const Points& points, double voxel_size_m, int min_hits, BufferStats* stats) {
  if (!(voxel_size_m > 0.0)) return points;
  struct Voxel {
    std::int64_t key[3];
    Vec3 sum;
    std::uint32_t count;
    std::uint32_t first;
  };
  std::vector<Voxel> voxels;
  std::vector<std::int32_t> table;
  std::size_t capacity = 16;
  while (capacity < 2 * points.size()) capacity *= 2;
  table.assign(capacity, -1);
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
      Voxel& vox = voxels[static_cast<std::size_t>(v)];
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

bool IsFinite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

// Push() and Build() of the reference buffer.
class Buffer {
 public:
  explicit Buffer(const PointCloudBuffer::Config& config) : config_(config) {}

  void Push(Scan scan) {
    const std::size_t before = scan.points_S.size();
    scan.points_S.erase(std::remove_if(scan.points_S.begin(), scan.points_S.end(),
                                       [](const Vec3& p) { return !IsFinite(p); }),
                        scan.points_S.end());
    const std::size_t non_finite = before - scan.points_S.size();
    scans_.push_back({std::move(scan), non_finite});
    while (scans_.size() > static_cast<std::size_t>(config_.max_scans)) scans_.pop_front();
  }

  PointCloudBuffer::LocalCloud Build() const {
    PointCloudBuffer::LocalCloud result;
    if (scans_.empty()) return result;
    const Scan& newest = scans_.back().first;
    result.time_s = newest.time_s;
    result.T_O_L = Eigen::Isometry3d::Identity();
    result.T_O_L.translation() = newest.T_O_S.translation();
    const Eigen::Isometry3d T_L_O = result.T_O_L.inverse();
    const double r2 = config_.crop_radius_m * config_.crop_radius_m;
    BufferStats& stats = result.stats;
    if (config_.voxel_size_m > 0.0) return BuildVoxels(result);
    Points merged_L;
    for (const auto& s : scans_) {
      stats.input += s.first.points_S.size() + s.second;
      stats.non_finite += s.second;
      const Eigen::Isometry3d T_L_S = T_L_O * s.first.T_O_S;
      for (const Vec3& p_S : s.first.points_S) {
        const Vec3 p_L = T_L_S * p_S;
        if (p_L.squaredNorm() > r2) {
          ++stats.out_of_range;
          continue;
        }
        merged_L.push_back(p_L);
      }
    }
    result.points_L = reference::Subsample(merged_L, config_.max_points, config_.seed, &stats);
    stats.output = result.points_L.size();
    return result;
  }

 private:
  // The voxel filter from scratch: every buffered point into a grid fixed in O, its position in its
  // voxel in 2^-20 of the edge, summed per voxel; each voxel with enough hits within the crop radius
  // is its centroid; subsampling keeps the voxels with the smallest seeded hash of their index.
  // The output as a set (sorted): the buffer's order is that of its voxel store.
  PointCloudBuffer::LocalCloud BuildVoxels(PointCloudBuffer::LocalCloud& result) const {
    constexpr double kSteps = 1048576.0;
    struct Sum {
      std::int64_t q[3] = {0, 0, 0};
      std::uint32_t count = 0;
    };
    std::map<std::array<std::int64_t, 3>, Sum> voxels;
    BufferStats& stats = result.stats;
    const double inv = 1.0 / config_.voxel_size_m;
    for (const auto& s : scans_) {
      stats.input += s.first.points_S.size() + s.second;
      stats.non_finite += s.second;
      for (const Vec3& p_S : s.first.points_S) {
        const Vec3 p_O = s.first.T_O_S * p_S;
        std::array<std::int64_t, 3> key;
        std::int64_t q[3];
        bool in_grid = true;
        for (int a = 0; a < 3; ++a) {
          const double f = p_O[a] * inv + (a == 2 ? 0.5 : 0.0);  // half a voxel lower vertically
          const double k = std::floor(f);
          if (!(k >= -2147483648.0 && k <= 2147483647.0)) {
            in_grid = false;
            break;
          }
          key[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(k);
          q[a] = std::min<std::int64_t>(static_cast<std::int64_t>((f - k) * kSteps), 1048575);
        }
        if (!in_grid) {
          ++stats.out_of_range;
          continue;
        }
        Sum& sum = voxels[key];
        for (int a = 0; a < 3; ++a) sum.q[a] += q[a];
        ++sum.count;
      }
    }
    const Vec3 origin = result.T_O_L.translation();
    const double r2 = config_.crop_radius_m * config_.crop_radius_m;
    const double near2 = config_.near_range_m * config_.near_range_m;
    const auto near_hits = static_cast<std::uint32_t>(std::max(config_.min_hits, config_.near_min_hits));
    std::vector<std::pair<std::uint64_t, Vec3>> kept;  // rank, point
    const std::uint64_t salt = Mix(config_.seed);
    for (const auto& [key, sum] : voxels) {
      if (sum.count < static_cast<std::uint32_t>(config_.min_hits)) {
        stats.voxel_sparse += sum.count;
        continue;
      }
      const double n = sum.count;
      Vec3 c;
      for (int a = 0; a < 3; ++a) {
        c[a] = config_.voxel_size_m * (static_cast<double>(key[static_cast<std::size_t>(a)]) - (a == 2 ? 0.5 : 0.0) +
                                       (static_cast<double>(sum.q[a]) + 0.5 * n) / (n * kSteps));
      }
      const Vec3 p_L = c - origin;
      if (p_L.squaredNorm() > r2) {
        stats.out_of_range += sum.count;
        continue;
      }
      if (sum.count < near_hits && p_L.squaredNorm() < near2) {
        stats.voxel_sparse += sum.count;
        continue;
      }
      const std::uint64_t hash = Mix(static_cast<std::uint64_t>(key[0]) * 0x9e3779b97f4a7c15ULL ^
                                     static_cast<std::uint64_t>(key[1]) * 0xc2b2ae3d27d4eb4fULL ^
                                     static_cast<std::uint64_t>(key[2]) * 0x165667b19e3779f9ULL);
      kept.emplace_back(Mix(salt ^ hash), p_L);
    }
    stats.voxels_kept = kept.size();
    if (kept.size() > config_.max_points) {
      std::nth_element(kept.begin(), kept.begin() + static_cast<std::ptrdiff_t>(config_.max_points), kept.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      stats.subsampled_out = kept.size() - config_.max_points;
      kept.resize(config_.max_points);
    }
    for (const auto& k : kept) result.points_L.push_back(k.second);
    SortPoints(&result.points_L);
    stats.output = result.points_L.size();
    return result;
  }

  PointCloudBuffer::Config config_;
  std::deque<std::pair<Scan, std::size_t>> scans_;
};

}  // namespace reference

// Bitwise equality of two clouds: same points, same order, same bits (NaN-safe, -0 != +0).
bool SameBits(const Points& a, const Points& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
}

bool SameBits(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), 16 * sizeof(double)) == 0;
}

// `as_set`: the points in any order (the voxel filter's output order is that of its voxel store).
void ExpectSameCloud(PointCloudBuffer::LocalCloud got, const PointCloudBuffer::LocalCloud& want, int step,
                     bool as_set) {
  if (as_set) SortPoints(&got.points_L);
  EXPECT_TRUE(SameBits(got.points_L, want.points_L)) << "push " << step << ": " << got.points_L.size() << " vs "
                                                      << want.points_L.size() << " points";
  EXPECT_TRUE(SameBits(got.T_O_L, want.T_O_L)) << "push " << step;
  EXPECT_EQ(std::memcmp(&got.time_s, &want.time_s, sizeof(double)), 0) << "push " << step;
  const BufferStats& g = got.stats;
  const BufferStats& w = want.stats;
  EXPECT_EQ(g.input, w.input) << "push " << step;
  EXPECT_EQ(g.non_finite, w.non_finite) << "push " << step;
  EXPECT_EQ(g.out_of_range, w.out_of_range) << "push " << step;
  EXPECT_EQ(g.voxel_sparse, w.voxel_sparse) << "push " << step;
  EXPECT_EQ(g.voxels_kept, w.voxels_kept) << "push " << step;
  EXPECT_EQ(g.subsampled_out, w.subsampled_out) << "push " << step;
  EXPECT_EQ(g.output, w.output) << "push " << step;
}

// Scans of the generated outdoor scene from a vehicle driving a seeded curve (odometry motion with
// yaw, roll and pitch), with seeded outliers and non-finite points, pushed into both buffers; every
// Build() after the buffer is full (evictions) and before must agree bit for bit.
void CompareWithReference(const PointCloudBuffer::Config& config, std::uint64_t seed, int pushes) {
  PointCloudBuffer buffer(config);
  reference::Buffer ref(config);
  const synth::Scene scene = synth::MakeOutdoorScene(seed);
  const SpinningLidarMount mount;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Vec3 position(-5.0 + 2.0 * unit(rng), -3.0 + 6.0 * unit(rng), 0.0);
  double yaw = 0.5 * gauss(rng);
  for (int i = 0; i < pushes; ++i) {
    const double t = 0.05 * i;
    position += Vec3(0.05 * std::cos(yaw), 0.05 * std::sin(yaw), 0.002 * gauss(rng));
    yaw += 0.02 * gauss(rng);
    Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
    T_O_B.linear() = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(0.02 * gauss(rng), Vec3::UnitY()) *
                      Eigen::AngleAxisd(0.02 * gauss(rng), Vec3::UnitX()))
                         .toRotationMatrix();
    T_O_B.translation() = position;
    std::vector<Scan> scans = synth::SimulateScans(scene, mount, T_O_B, t, 1, 0.015, seed * 1000 + static_cast<std::uint64_t>(i));
    Scan scan = std::move(scans.front());
    // Outliers anywhere within 40 m (some beyond the crop radius), and a few non-finite points.
    for (int k = 0; k < 50; ++k) scan.points_S.emplace_back(80 * unit(rng) - 40, 80 * unit(rng) - 40, 10 * unit(rng) - 5);
    if (i % 3 == 0) scan.points_S.insert(scan.points_S.begin() + 7, Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
    if (i % 5 == 0) scan.points_S.emplace_back(0.0, -std::numeric_limits<double>::infinity(), 1.0);
    buffer.Push(scan);
    ref.Push(scan);
    if (i % 2 == 1 || i + 1 == pushes) ExpectSameCloud(buffer.Build(), ref.Build(), i, config.voxel_size_m > 0.0);
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(PointCloudBufferTest, BuildMatchesTheReferenceBitForBit) {
  PointCloudBuffer::Config config;
  config.max_scans = 10;
  config.max_points = 6000;
  CompareWithReference(config, 1, 40);
}

TEST(PointCloudBufferTest, BuildMatchesTheReferenceWithOtherSettings) {
  PointCloudBuffer::Config config;
  config.max_scans = 4;
  config.voxel_size_m = 0.25;
  config.min_hits = 3;
  config.crop_radius_m = 12.0;
  config.max_points = 100000;  // no subsampling
  config.seed = 7;
  CompareWithReference(config, 2, 15);
  config.voxel_size_m = 0.0;  // filter off
  config.max_points = 2000;
  CompareWithReference(config, 3, 12);
  config.voxel_size_m = 0.05;
  config.min_hits = 1;
  config.crop_radius_m = 200.0;
  CompareWithReference(config, 4, 12);
  config.crop_radius_m = 1e9;
  config.min_hits = 2;
  CompareWithReference(config, 5, 12);
}

// The voxels are summed in integers, so what comes out depends on the scans in the buffer only: a
// buffer that saw 30 scans (and let 20 go) gives the same cloud as one that saw only the last 10.
TEST(PointCloudBufferTest, TheCloudDependsOnlyOnTheBufferedScans) {
  PointCloudBuffer::Config config;
  config.max_scans = 10;
  config.max_points = 5000;
  PointCloudBuffer long_lived(config), fresh(config);
  const synth::Scene scene = synth::MakeOutdoorScene(3);
  const SpinningLidarMount mount;
  for (int i = 0; i < 30; ++i) {
    Eigen::Isometry3d T_O_B = Pose(Vec3(0.2 * i, 0.05 * i, 0.0), 0.03 * i);
    Scan scan = std::move(synth::SimulateScans(scene, mount, T_O_B, 0.05 * i, 1, 0.015, 77 + i).front());
    long_lived.Push(scan);
    if (i >= 20) fresh.Push(scan);
  }
  PointCloudBuffer::LocalCloud a = long_lived.Build(), b = fresh.Build();
  EXPECT_GT(a.stats.subsampled_out, 0u);
  SortPoints(&b.points_L);
  ExpectSameCloud(a, b, 29, true);
}

// Flat ground at O's origin height (where the vehicle starts), hit a centimetre above and below, is
// one layer of centroids: the grid's vertical boundaries are half a voxel off it.
TEST(PointCloudBufferTest, GroundAtTheStartHeightIsOneLayer) {
  PointCloudBuffer buffer;  // 0.1 m voxels
  Points scan;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      for (const double z : {-0.01, 0.01, -0.004, 0.006}) scan.emplace_back(0.1 * i + 0.03, 0.1 * j + 0.04, z);
    }
  }
  Eigen::Isometry3d T_O_S = Eigen::Isometry3d::Identity();
  T_O_S.translation() = Vec3(0.0, 0.0, 1.88);
  for (Vec3& p : scan) p.z() -= 1.88;  // in S
  buffer.Push({scan, T_O_S, 0.0});
  const auto cloud = buffer.Build();
  ASSERT_EQ(cloud.points_L.size(), 400u);
  for (const Vec3& p : cloud.points_L) EXPECT_NEAR(p.z(), 0.0005 - 1.88, 1e-6);
}

// A point beyond the grid's voxel indices (2^31 voxels from O's origin) is dropped and counted as out
// of range, never converted out of range or merged with others.
TEST(PointCloudBufferTest, PointsBeyondTheGridAreCountedOutOfRange) {
  PointCloudBuffer::Config config;
  config.crop_radius_m = 1e30;
  PointCloudBuffer buffer(config);
  Points scan = {Vec3(1.01, 0.01, 0.01), Vec3(1.02, 0.02, 0.02), Vec3(3e8, 0.0, 0.0), Vec3(3e8, 0.0, 0.0),
                 Vec3(0.0, -1e300, 0.0), Vec3(0.0, -1e300, 0.0)};
  buffer.Push({scan, Eigen::Isometry3d::Identity(), 0.0});
  const auto cloud = buffer.Build();
  EXPECT_EQ(cloud.stats.out_of_range, 4u);
  ASSERT_EQ(cloud.points_L.size(), 1u);
  EXPECT_NEAR(cloud.points_L[0].x(), 1.015, 1e-6);
}

TEST(PointCloudBufferTest, VoxelsNearTheSensorNeedNearMinHits) {
  // One scan from a sensor 2 m up: two stray returns sharing a voxel 1.5 m from the sensor, a
  // surface patch hit six times in a voxel 2 m away, and two returns sharing a voxel 8 m away.
  Scan scan;
  scan.T_O_S = Pose(Vec3(0.0, 0.0, 2.0), 0.0);
  const auto add = [&scan](const Vec3& p, int n) {
    for (int i = 0; i < n; ++i) scan.points_S.push_back(p + Vec3(0.01 * i, 0.005 * i, 0.0));
  };
  add(Vec3(1.52, 0.03, -0.47), 2);  // stray pair
  add(Vec3(2.03, 0.02, -0.47), 6);  // surface
  add(Vec3(8.03, 0.02, -1.97), 2);  // far pair
  const auto near_of = [](const Points& pts, double range_m) {
    return std::count_if(pts.begin(), pts.end(), [range_m](const Vec3& p) { return p.norm() < range_m; });
  };
  PointCloudBuffer::Config config;
  config.voxel_size_m = 0.1;
  PointCloudBuffer paper(config);  // min_hits everywhere
  paper.Push(scan);
  const Points all = paper.Build().points_L;
  EXPECT_EQ(all.size(), 3u);
  config.near_range_m = 3.0;
  config.near_min_hits = 4;
  PointCloudBuffer near(config);
  near.Push(scan);
  const Points kept = near.Build().points_L;
  ASSERT_EQ(kept.size(), 2u);  // the stray pair is gone
  EXPECT_EQ(near_of(kept, 1.8), 0);
  EXPECT_EQ(near_of(kept, 3.0), 1);
  EXPECT_GT(kept[0].norm() + kept[1].norm(), 9.0);  // the far pair stays
  config.near_min_hits = 0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
  config.near_min_hits = 4;
  config.near_range_m = -1.0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}

TEST(PointCloudBufferTest, VoxelFilterAndSubsampleMatchTheReference) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-30.0, 30.0);
  Points pts;
  for (int i = 0; i < 20000; ++i) pts.emplace_back(u(rng), u(rng), 0.05 * u(rng));
  for (int i = 0; i < 2000; ++i) pts.push_back(pts[static_cast<std::size_t>(i) * 7]);  // repeated hits
  // Points on voxel boundaries, at signed zero and far away.
  for (double v : {0.0, -0.0, -1.0, -0.5, 2.0, -3.0, 1e-300, -1e-300}) {
    pts.emplace_back(v, -v, v);
    pts.emplace_back(v, v, -v);
  }
  pts.emplace_back(5e7, -3e8, 1e9);
  pts.emplace_back(-4e15, 1e16, -2.5e15);
  for (double voxel : {0.1, 0.3, 1.0, 0.0}) {
    for (int min_hits : {1, 2}) {
      BufferStats a, b;
      const Points got = VoxelFilter(pts, voxel, min_hits, &a);
      const Points want = reference::VoxelFilter(pts, voxel, min_hits, &b);
      EXPECT_TRUE(SameBits(got, want)) << voxel << " " << min_hits;
      EXPECT_EQ(a.voxel_sparse, b.voxel_sparse);
      EXPECT_EQ(a.voxels_kept, b.voxels_kept);
    }
  }
  for (std::size_t n : {std::size_t{4}, std::size_t{1000}, std::size_t{21999}, std::size_t{22001}, std::size_t{50000}}) {
    BufferStats a, b;
    EXPECT_TRUE(SameBits(Subsample(pts, n, 3, &a), reference::Subsample(pts, n, 3, &b))) << n;
    EXPECT_EQ(a.subsampled_out, b.subsampled_out);
  }
}

// A coordinate too far for a 64-bit voxel index (1e30 m at 0.1 m) once merged every point into one
// voxel (an out-of-range double-to-int conversion); it is dropped and counted instead.
TEST(PointCloudBufferTest, VoxelFilterDropsPointsBeyondAnyVoxelIndex) {
  Points points;
  for (int i = 0; i < 10; ++i) {
    points.emplace_back(0.05 + i, 0.05, 0.05);  // ten voxels, two hits each
    points.emplace_back(0.06 + i, 0.05, 0.05);
  }
  points.emplace_back(1e30, 0.0, 0.0);
  points.emplace_back(1e30, 0.0, 0.0);
  BufferStats stats;
  const Points out = VoxelFilter(points, 0.1, 2, &stats);
  EXPECT_EQ(out.size(), 10u);
  EXPECT_EQ(stats.out_of_range, 2u);
  for (const Vec3& p : out) EXPECT_LT(p.norm(), 10.0);
}

TEST(PointCloudBufferTest, KnownPosesGiveKnownPointsInTheNewestSensorFrame) {
  PointCloudBuffer buffer(NoFilter());
  // Scan 1: sensor at (1, 2, 1.88) facing +y (yaw 90 deg); a point 3 m ahead in the sensor frame.
  buffer.Push({{Vec3(3, 0, 0)}, Pose(Vec3(1, 2, 1.88), DegToRad(90)), 0.0});
  // Scan 2 (newest): sensor at (4, 2, 1.88), yaw 0; a point 1 m to its left.
  buffer.Push({{Vec3(0, 1, 0)}, Pose(Vec3(4, 2, 1.88), 0.0), 0.05});
  const auto cloud = buffer.Build();
  ASSERT_EQ(cloud.points_L.size(), 2u);
  // L has the odometry axes and the newest sensor position as origin.
  EXPECT_TRUE(cloud.T_O_L.translation().isApprox(Vec3(4, 2, 1.88)));
  EXPECT_TRUE(cloud.T_O_L.linear().isIdentity());
  // Scan 1's point is at (1, 5, 1.88) in O, so (-3, 3, 0) in L.
  EXPECT_TRUE(cloud.points_L[0].isApprox(Vec3(-3, 3, 0), 1e-12)) << cloud.points_L[0].transpose();
  EXPECT_TRUE(cloud.points_L[1].isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_DOUBLE_EQ(cloud.time_s, 0.05);
}

TEST(PointCloudBufferTest, KeepsOnlyTheLastScans) {
  auto config = NoFilter();
  config.max_scans = 3;
  PointCloudBuffer buffer(config);
  for (int i = 0; i < 5; ++i) buffer.Push({{Vec3(i + 1.0, 0, 0)}, Eigen::Isometry3d::Identity(), 0.1 * i});
  EXPECT_EQ(buffer.num_scans(), 3u);
  const auto cloud = buffer.Build();
  ASSERT_EQ(cloud.points_L.size(), 3u);
  EXPECT_DOUBLE_EQ(cloud.points_L[0].x(), 3.0);
}

TEST(PointCloudBufferTest, SingleHitOutliersAreDroppedByTheVoxelFilter) {
  PointCloudBuffer::Config config;  // 0.1 m voxels, at least 2 hits
  PointCloudBuffer buffer(config);
  Points scan;
  for (int i = 0; i < 10; ++i) {
    scan.emplace_back(2.02, 0.03 + 0.3 * i, 0.05);  // hit twice (next line)
    scan.emplace_back(2.04, 0.05 + 0.3 * i, 0.06);
  }
  scan.emplace_back(7.55, 3.05, 1.05);   // a lone outlier
  scan.emplace_back(-4.05, 1.05, 0.55);  // another
  buffer.Push({scan, Eigen::Isometry3d::Identity(), 0.0});
  const auto cloud = buffer.Build();
  EXPECT_EQ(cloud.points_L.size(), 10u);
  EXPECT_EQ(cloud.stats.voxel_sparse, 2u);
  for (const Vec3& p : cloud.points_L) EXPECT_NEAR(p.x(), 2.03, 1e-6);  // voxel centroids (to 2^-20 of a voxel)
}

TEST(PointCloudBufferTest, CropNonFiniteAndSubsampleAreCounted) {
  auto config = NoFilter();
  config.crop_radius_m = 10.0;
  config.max_points = 100;
  PointCloudBuffer buffer(config);
  Points scan;
  for (int i = 0; i < 300; ++i) scan.emplace_back(0.01 * i, 1.0, 0.0);
  scan.emplace_back(50.0, 0.0, 0.0);
  scan.emplace_back(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  scan.emplace_back(0.0, std::numeric_limits<double>::infinity(), 0.0);
  buffer.Push({scan, Eigen::Isometry3d::Identity(), 0.0});
  const auto a = buffer.Build();
  EXPECT_EQ(a.stats.input, 303u);
  EXPECT_EQ(a.stats.non_finite, 2u);
  EXPECT_EQ(a.stats.out_of_range, 1u);
  EXPECT_EQ(a.stats.subsampled_out, 200u);
  EXPECT_EQ(a.stats.output, 100u);
  ASSERT_EQ(a.points_L.size(), 100u);
  // Deterministic, and spread over the whole line rather than its start.
  EXPECT_EQ(a.points_L, buffer.Build().points_L);
  EXPECT_LT(a.points_L.front().x(), 0.3);
  EXPECT_GT(a.points_L.back().x(), 2.7);
}

TEST(PointCloudBufferTest, EmptyBufferBuildsAnEmptyCloudAndBadInputThrows) {
  PointCloudBuffer buffer;
  EXPECT_TRUE(buffer.Build().points_L.empty());
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(buffer.Push({{Vec3(1, 0, 0)}, bad, 0.0}), std::invalid_argument);
  PointCloudBuffer::Config config;
  config.max_scans = 0;
  EXPECT_THROW(PointCloudBuffer{config}, std::invalid_argument);
  config = PointCloudBuffer::Config{};
  config.min_hits = 0;
  EXPECT_THROW(config.Validate(), std::invalid_argument);
}

TEST(PointCloudBufferTest, SubsampleKeepsOrderAndIsSeeded) {
  Points pts;
  for (int i = 0; i < 1000; ++i) pts.emplace_back(i, 0, 0);
  const Points a = Subsample(pts, 100, 1);
  const Points b = Subsample(pts, 100, 2);
  ASSERT_EQ(a.size(), 100u);
  EXPECT_NE(a, b);
  for (std::size_t i = 1; i < a.size(); ++i) EXPECT_LT(a[i - 1].x(), a[i].x());
  EXPECT_EQ(Subsample(pts, 5000, 1), pts);
}

}  // namespace
}  // namespace ovpc

