#include "ovpc/sim/vlp16.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "random.h"

namespace ovpc::sim {
namespace {

constexpr int kLasers = 16;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Firing and step times are sums of floating-point periods: times this close are equal (a firing
// period is 55 us).
constexpr double kTimeEpsilon_s = 1e-9;

struct ElevationTable {
  double cos_e[kLasers];
  double sin_e[kLasers];
  ElevationTable() {
    for (int i = 0; i < kLasers; ++i) {
      cos_e[i] = std::cos(DegToRad(synth::kVlp16ElevationDeg[static_cast<std::size_t>(i)]));
      sin_e[i] = std::sin(DegToRad(synth::kVlp16ElevationDeg[static_cast<std::size_t>(i)]));
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
  const synth::SpinningLidarMount& m = mount;
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
    : config_(config), caster_(caster), t0_s_(t0_s), rng_(std::make_unique<Rng>()) {
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
  const std::int64_t scan_index = next_firing_ / firings_per_scan_;
  current_ = TrueScan{};
  current_points_W_.clear();
  current_points_W_.reserve(rays_per_scan());
  rng_->Seed(HashCombine(config_.seed, static_cast<std::uint64_t>(scan_index)));
}

std::vector<double> Vlp16Sim::CastFiring(const Eigen::Isometry3d& T_W_S, double azimuth_rad) const {
  std::vector<double> ranges(kLasers, kInf);
  const Vec3 origin_W = T_W_S.translation();
  for (int laser = 0; laser < kLasers; ++laser) {
    const Vec3 dir_W = T_W_S.linear() * BeamDirection(laser, azimuth_rad);
    const RayCaster::Hit hit = caster_->Cast(origin_W, dir_W, config_.mount.max_range_m);
    if (hit.hit() && hit.range_m >= config_.mount.min_range_m) {
      ranges[static_cast<std::size_t>(laser)] = hit.range_m;
    }
  }
  return ranges;
}

void Vlp16Sim::Advance(const TimedPose& from, const TimedPose& to,
                       std::vector<TrueScan>* completed) {
  const synth::SpinningLidarMount& mount = config_.mount;
  const ElevationTable& e = Elevations();
  const bool dropouts = config_.dropout_fraction > 0.0;
  const bool outliers = config_.outlier_fraction > 0.0;
  const double sigma = config_.range_sigma_m;
  const double extra_sigma = config_.extra_noise_sigma_m;
  Rng& rng = *rng_;

  for (;;) {
    const double t_s = t0_s_ + static_cast<double>(next_firing_) * firing_period_s_;
    const int j = static_cast<int>(next_firing_ % firings_per_scan_);
    // A scan ends where the next one's first firing would be.
    if (j == 0 && next_firing_ > 0 && current_.rays > 0) {
      if (t_s > to.time_s + kTimeEpsilon_s) break;  // the end pose is not known yet
      current_.time_s = t_s;
      current_.T_W_S = InterpolatePose(from, to, t_s) * mount.T_B_S(t_s);
      const Eigen::Isometry3d T_S_W = current_.T_W_S.inverse();
      current_.points_S.reserve(current_points_W_.size());
      for (const Vec3& p_W : current_points_W_) current_.points_S.push_back(T_S_W * p_W);
      if (completed != nullptr) completed->push_back(std::move(current_));
      StartScan();
    }
    if (t_s >= to.time_s - kTimeEpsilon_s) break;  // belongs to the next interval

    const Eigen::Isometry3d T_W_S = InterpolatePose(from, to, t_s) * mount.T_B_S(t_s);
    const Eigen::Matrix3d& R_W_S = T_W_S.linear();
    const Vec3 origin_W = T_W_S.translation();
    const double ca = cos_azimuth_[static_cast<std::size_t>(j)];
    const double sa = sin_azimuth_[static_cast<std::size_t>(j)];
    for (int laser = 0; laser < kLasers; ++laser) {
      const Vec3 dir_S(e.cos_e[laser] * ca, e.cos_e[laser] * sa, e.sin_e[laser]);
      const Vec3 dir_W = R_W_S * dir_S;
      const RayCaster::Hit hit = caster_->Cast(origin_W, dir_W, mount.max_range_m);
      ++current_.rays;
      double range_m = hit.range_m;
      bool has_return = hit.hit();
      if (outliers && rng.Uniform() < config_.outlier_fraction) {
        // Dust, rain, multipath: a return anywhere in front of what the beam would have hit.
        range_m = rng.Uniform(mount.min_range_m, has_return ? range_m : mount.max_range_m);
        has_return = true;
        ++current_.outliers;
      } else if (has_return) {
        if (sigma > 0.0) range_m += sigma * rng.Gaussian();
        if (extra_sigma > 0.0) range_m += extra_sigma * rng.Gaussian();
      }
      if (!has_return) continue;
      if (dropouts && rng.Uniform() < config_.dropout_fraction) {
        ++current_.dropouts;
        continue;
      }
      if (range_m < mount.min_range_m || range_m > mount.max_range_m) continue;
      current_points_W_.push_back(origin_W + range_m * dir_W);
    }
    ++next_firing_;
  }
}

}  // namespace ovpc::sim
