#include "ovpc/sim/vlp16.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "random.h"

namespace ovpc::sim {
namespace {

constexpr int kLasers = 16;
static_assert(kLasers <= RayCaster::kFanSize, "a firing must fit in one packet");
constexpr double kInf = std::numeric_limits<double>::infinity();
// Firing and step times are sums of floating-point periods: times this close are equal (a firing
// period is 55 us).
constexpr double kTimeEpsilon_s = 1e-9;

struct ElevationTable {
  double cos_e[kLasers];
  double sin_e[kLasers];
  ElevationTable() {
    for (int i = 0; i < kLasers; ++i) {
      cos_e[i] = std::cos(DegToRad(kVlp16ElevationDeg[static_cast<std::size_t>(i)]));
      sin_e[i] = std::sin(DegToRad(kVlp16ElevationDeg[static_cast<std::size_t>(i)]));
    }
  }
};

const ElevationTable& Elevations() {
  static const ElevationTable table;
  return table;
}

}  // namespace

Eigen::Isometry3d InterpolatePose(const TimedPose& a, const TimedPose& b, double time_s) {
  const double span = b.time_s - a.time_s;
  double s = span > 0.0 ? (time_s - a.time_s) / span : 1.0;
  s = std::min(1.0, std::max(0.0, s));
  const Eigen::Quaterniond qa(a.T_W_B.linear());
  const Eigen::Quaterniond qb(b.T_W_B.linear());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = qa.slerp(s, qb).toRotationMatrix();
  T.translation() = (1.0 - s) * a.T_W_B.translation() + s * b.T_W_B.translation();
  return T;
}

void Vlp16Sim::Config::Validate() const {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("Vlp16Sim::Config: " + what);
  };
  const SpinningLidarMount& m = mount;
  require(std::isfinite(m.height_m), "mount.height_m must be finite");
  require(std::isfinite(m.tilt_rad), "mount.tilt_rad must be finite");
  require(std::isfinite(m.spin_hz), "mount.spin_hz must be finite");
  require(m.scan_hz > 0.0 && std::isfinite(m.scan_hz), "mount.scan_hz must be > 0");
  require(m.azimuth_step_rad > 0.0 && m.azimuth_step_rad <= kPi,
          "mount.azimuth_step_rad must be in (0, pi]");
  require(m.min_range_m >= 0.0 && m.max_range_m > m.min_range_m && std::isfinite(m.max_range_m),
          "mount.min_range_m/max_range_m must satisfy 0 <= min < max < inf");
  require(range_sigma_m >= 0.0 && std::isfinite(range_sigma_m), "range_sigma_m must be >= 0");
  require(dropout_fraction >= 0.0 && dropout_fraction <= 1.0, "dropout_fraction must be in [0, 1]");
  require(outlier_fraction >= 0.0 && outlier_fraction <= 1.0, "outlier_fraction must be in [0, 1]");
  require(extra_noise_sigma_m >= 0.0 && std::isfinite(extra_noise_sigma_m),
          "extra_noise_sigma_m must be >= 0");
}

Vlp16Sim::Vlp16Sim(const Config& config, const RayCaster* caster, double t0_s)
    : config_(config), caster_(caster), t0_s_(t0_s) {
  config_.Validate();
  if (caster_ == nullptr) throw std::invalid_argument("Vlp16Sim: caster is null");
  if (!std::isfinite(t0_s)) throw std::invalid_argument("Vlp16Sim: t0_s must be finite");
  firings_per_scan_ = static_cast<int>(std::lround(2.0 * kPi / config_.mount.azimuth_step_rad));
  firing_period_s_ = 1.0 / (config_.mount.scan_hz * firings_per_scan_);
  cos_azimuth_.resize(static_cast<std::size_t>(firings_per_scan_));
  sin_azimuth_.resize(static_cast<std::size_t>(firings_per_scan_));
  for (int j = 0; j < firings_per_scan_; ++j) {
    cos_azimuth_[static_cast<std::size_t>(j)] = std::cos(j * config_.mount.azimuth_step_rad);
    sin_azimuth_[static_cast<std::size_t>(j)] = std::sin(j * config_.mount.azimuth_step_rad);
  }
  StartScan();
}

Vlp16Sim::~Vlp16Sim() = default;
Vlp16Sim::Vlp16Sim(Vlp16Sim&&) noexcept = default;
Vlp16Sim& Vlp16Sim::operator=(Vlp16Sim&&) noexcept = default;

Vec3 Vlp16Sim::BeamDirection(int laser, double azimuth_rad) {
  const ElevationTable& e = Elevations();
  return Vec3(e.cos_e[laser] * std::cos(azimuth_rad), e.cos_e[laser] * std::sin(azimuth_rad),
              e.sin_e[laser]);
}

void Vlp16Sim::StartScan() {
  current_ = TrueScan{};
  current_points_W_.clear();
  current_points_W_.reserve(rays_per_scan());
  pending_.clear();
  pending_.reserve(static_cast<std::size_t>(firings_per_scan_));
}

std::vector<double> Vlp16Sim::CastFiring(const Eigen::Isometry3d& T_W_S, double azimuth_rad) const {
  std::vector<double> ranges(kLasers, kInf);
  const Vec3 origin_W = T_W_S.translation();
  Vec3 dirs_W[kLasers];
  RayCaster::Hit hits[kLasers];
  for (int laser = 0; laser < kLasers; ++laser) {
    dirs_W[laser] = T_W_S.linear() * BeamDirection(laser, azimuth_rad);
  }
  caster_->CastFan(origin_W, dirs_W, kLasers, config_.mount.max_range_m, hits);
  for (int laser = 0; laser < kLasers; ++laser) {
    if (hits[laser].hit() && hits[laser].range_m >= config_.mount.min_range_m) {
      ranges[static_cast<std::size_t>(laser)] = hits[laser].range_m;
    }
  }
  return ranges;
}

// What one firing gave: its returns in the world frame, in laser order, and its fault counts.
struct Vlp16Sim::FiringReturns {
  Vec3 points_W[kLasers];
  int count = 0;
  int dropouts = 0;
  int outliers = 0;
};

void Vlp16Sim::CastOne(const Firing& firing, FiringReturns* out) const {
  const SpinningLidarMount& mount = config_.mount;
  const ElevationTable& e = Elevations();
  // The firing's own stream: the same draws whichever thread casts it, and in whatever order.
  Rng rng(HashCombine(config_.seed, static_cast<std::uint64_t>(firing.index)));
  const double ca = cos_azimuth_[static_cast<std::size_t>(firing.azimuth)];
  const double sa = sin_azimuth_[static_cast<std::size_t>(firing.azimuth)];
  // The 16 lasers of a firing leave together: one Embree packet.
  Vec3 dirs_W[kLasers];
  RayCaster::Hit hits[kLasers];
  for (int laser = 0; laser < kLasers; ++laser) {
    dirs_W[laser] = firing.R_W_S * Vec3(e.cos_e[laser] * ca, e.cos_e[laser] * sa, e.sin_e[laser]);
  }
  caster_->CastFan(firing.origin_W, dirs_W, kLasers, mount.max_range_m, hits);
  const bool dropouts = config_.dropout_fraction > 0.0;
  const bool outliers = config_.outlier_fraction > 0.0;
  const double sigma = config_.range_sigma_m;
  const double extra_sigma = config_.extra_noise_sigma_m;
  *out = FiringReturns{};
  for (int laser = 0; laser < kLasers; ++laser) {
    const RayCaster::Hit& hit = hits[laser];
    double range_m = hit.range_m;
    bool has_return = hit.hit();
    if (outliers && rng.Uniform() < config_.outlier_fraction) {
      // Dust, rain, multipath: a return anywhere in front of what the beam would have hit.
      range_m = rng.Uniform(mount.min_range_m, has_return ? range_m : mount.max_range_m);
      has_return = true;
      ++out->outliers;
    } else if (has_return) {
      if (sigma > 0.0) range_m += sigma * rng.Gaussian();
      if (extra_sigma > 0.0) range_m += extra_sigma * rng.Gaussian();
    }
    if (!has_return) continue;
    if (dropouts && rng.Uniform() < config_.dropout_fraction) {
      ++out->dropouts;
      continue;
    }
    if (range_m < mount.min_range_m || range_m > mount.max_range_m) continue;
    out->points_W[out->count++] = firing.origin_W + range_m * dirs_W[laser];
  }
}

void Vlp16Sim::CastPending() {
  if (pending_.empty()) return;
  thread_local std::vector<FiringReturns> returns;
  returns.resize(pending_.size());
  FiringReturns* out = returns.data();  // this thread's; other threads write through the pointer
  const std::function<void(std::size_t)> fn = [this, out](std::size_t i) { CastOne(pending_[i], &out[i]); };
  if (parallel_for_) {
    parallel_for_(pending_.size(), fn);
  } else {
    for (std::size_t i = 0; i < pending_.size(); ++i) fn(i);
  }
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const FiringReturns& r = returns[i];
    current_.rays += kLasers;
    current_.dropouts += static_cast<std::size_t>(r.dropouts);
    current_.outliers += static_cast<std::size_t>(r.outliers);
    current_points_W_.insert(current_points_W_.end(), r.points_W, r.points_W + r.count);
  }
  pending_.clear();
}

void Vlp16Sim::Advance(const TimedPose& from, const TimedPose& to,
                       std::vector<TrueScan>* completed) {
  const SpinningLidarMount& mount = config_.mount;
  // Per-call parts of the per-firing pose (the same as InterpolatePose * mount.T_B_S, cheaper).
  const Eigen::Quaterniond q_from(from.T_W_B.linear());
  const Eigen::Quaterniond q_to(to.T_W_B.linear());
  const double span_s = to.time_s - from.time_s;
  const Eigen::Matrix3d R_tilt =
      Eigen::AngleAxisd(mount.tilt_rad, Vec3::UnitX()).toRotationMatrix();
  const Vec3 mast_B(0.0, 0.0, mount.height_m);

  for (;;) {
    const double t_s = t0_s_ + static_cast<double>(next_firing_) * firing_period_s_;
    const int j = static_cast<int>(next_firing_ % firings_per_scan_);
    // A scan ends where the next one's first firing would be.
    if (j == 0 && next_firing_ > 0 && (current_.rays > 0 || !pending_.empty())) {
      if (t_s > to.time_s + kTimeEpsilon_s) break;  // the end pose is not known yet
      CastPending();
      current_.time_s = t_s;
      current_.T_W_S = InterpolatePose(from, to, t_s) * mount.T_B_S(t_s);
      const Eigen::Isometry3d T_S_W = current_.T_W_S.inverse();
      current_.points_S.reserve(current_points_W_.size());
      for (const Vec3& p_W : current_points_W_) current_.points_S.push_back(T_S_W * p_W);
      if (completed != nullptr) completed->push_back(std::move(current_));
      StartScan();
    }
    if (t_s >= to.time_s - kTimeEpsilon_s) break;  // belongs to the next interval

    const double s = span_s > 0.0 ? std::clamp((t_s - from.time_s) / span_s, 0.0, 1.0) : 1.0;
    const Eigen::Matrix3d R_W_B = q_from.slerp(s, q_to).toRotationMatrix();
    const Vec3 p_W_B = (1.0 - s) * from.T_W_B.translation() + s * to.T_W_B.translation();
    const double yaw = 2.0 * kPi * std::fmod(mount.spin_hz * t_s, 1.0);
    Eigen::Matrix3d R_spin = Eigen::Matrix3d::Identity();
    R_spin(0, 0) = R_spin(1, 1) = std::cos(yaw);
    R_spin(1, 0) = std::sin(yaw);
    R_spin(0, 1) = -R_spin(1, 0);
    pending_.push_back({next_firing_, j, R_W_B * (R_spin * R_tilt), p_W_B + R_W_B * mast_B});
    ++next_firing_;
  }
}

}  // namespace ovpc::sim
