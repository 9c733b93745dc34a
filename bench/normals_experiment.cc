// The paper's normal-estimation experiment: angular error of OVPC vertex normals and of PCA normals
// (radius 0.3 m) on a flat ground plus an inclined plane of slope alpha, alpha from 0 to 35 deg.
// See bench/include/ovpc/bench/normals_experiment.h for the scene and the metric, and
// docs/PAPER_REPRODUCTION.md for the figures.
//
// Outputs (in --out-dir): normals_ovpc.csv and normals_pca.csv, one row per alpha
// (alpha_deg, mean_deg, sd_deg, median_deg, p95_deg, n, n_without_normal, n_over_90, points, p90_deg:
// n points with a normal, n_without_normal without one, n_over_90 of the n with an error above
// 90 deg, i.e. facing the wrong side; points in the bundled cloud);
// normals_pca_visible.csv (the PCA errors on OVPC's visible points only, a like-for-like check);
// normals_ovpc_mean_of_faces.csv or normals_ovpc_plane_fit.csv (the same meshes' vertex normals
// under the other rule than --vertex-normals, so that every run reports both);
// normals_pca_eigen.csv with --pca both; normals_summary.json (settings, means over alpha, times).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "ovpc/baselines/pca_normals.h"
#include "ovpc/bench/normals_experiment.h"
#include "ovpc/bench/report.h"
#include "ovpc/bench/stats.h"
#if defined(OVPC_HAVE_PCL)
#include "ovpc/baselines/pcl_normals.h"
#endif

namespace ovpc::bench {
namespace {

constexpr bool kHavePcl =
#if defined(OVPC_HAVE_PCL)
    true;
#else
    false;
#endif

struct Options {
  double alpha_min_deg = 0.0;
  double alpha_max_deg = 35.0;
  double step_deg = 0.1;
  std::uint64_t seed = 1;
  std::string pca = "auto";
  std::string out_dir = "out/normals";
  double points_alpha_deg = -1.0;
  std::string points_csv;
  bool quiet = false;
  SlopeSceneConfig scene;
  double pca_radius_m = 0.3;
  double gamma = OvpcMapper::Config{}.ghpr.gamma;
  VertexNormals::Rule vertex_normals = OvpcMapper::Config{}.vertex_normals.rule;
  bool unoriented = false;
  OvpcInputFilter filter;
};

/// One CSV row: the error statistics of one method at one alpha.
struct AlphaRow {
  double alpha_deg = 0.0;
  SampleStats stats;
  std::size_t without_normal = 0;
  std::size_t points = 0;
  std::size_t over_90 = 0;  ///< errors above 90 deg: normals facing away from the true side
};

struct MethodSeries {
  std::string name;
  std::string file;
  std::vector<AlphaRow> rows;
  double total_ms = 0.0;
};

/// With `unoriented`, errors are taken as unoriented lines (UnorientedDeg), a diagnostic of how
/// much of the error is orientation.
AlphaRow MakeRow(double alpha_deg, const MethodErrors& errors, std::size_t points,
                 bool unoriented) {
  std::vector<double> degrees = errors.Degrees();
  AlphaRow row{alpha_deg, {}, errors.without_normal, points, 0};
  for (double& e : degrees) {
    row.over_90 += e > 90.0 ? 1 : 0;
    if (unoriented) e = UnorientedDeg(e);
  }
  row.stats = Summarize(std::move(degrees));
  return row;
}

bool WriteSeries(const std::string& path, const MethodSeries& series) {
  std::ofstream out(path);
  if (!out) return false;
  out << "alpha_deg,mean_deg,sd_deg,median_deg,p95_deg,n,n_without_normal,n_over_90,points,p90_deg\n";
  char buffer[256];
  for (const AlphaRow& r : series.rows) {
    std::snprintf(buffer, sizeof(buffer), "%.2f,%.6f,%.6f,%.6f,%.6f,%zu,%zu,%zu,%zu,%.6f\n",
                  r.alpha_deg, r.stats.mean, r.stats.sd, r.stats.median, r.stats.p95, r.stats.n,
                  r.without_normal, r.over_90, r.points, r.stats.p90);
    out << buffer;
  }
  return static_cast<bool>(out);
}

/// Means over alpha of the per-alpha mean and sd (every alpha weighs the same, as in the paper's
/// "mean over all slope angles").
struct OverAlpha {
  double mean_of_means = 0.0;
  double mean_of_sds = 0.0;
  double mean_of_medians = 0.0;
  double mean_of_p95 = 0.0;
  double mean_of_p90 = 0.0;
  double share_over_90 = 0.0;  ///< of all evaluated points, over every alpha
};

OverAlpha Average(const MethodSeries& series) {
  OverAlpha a;
  if (series.rows.empty()) return a;
  std::size_t evaluated = 0;
  std::size_t over_90 = 0;
  for (const AlphaRow& r : series.rows) {
    evaluated += r.stats.n;
    over_90 += r.over_90;
    a.mean_of_means += r.stats.mean;
    a.mean_of_sds += r.stats.sd;
    a.mean_of_medians += r.stats.median;
    a.mean_of_p95 += r.stats.p95;
    a.mean_of_p90 += r.stats.p90;
  }
  const double n = static_cast<double>(series.rows.size());
  a.mean_of_means /= n;
  a.mean_of_sds /= n;
  a.mean_of_medians /= n;
  a.mean_of_p95 /= n;
  a.mean_of_p90 /= n;
  a.share_over_90 = evaluated > 0 ? static_cast<double>(over_90) / evaluated : 0.0;
  return a;
}

bool WritePointErrors(const std::string& path,
                      const std::vector<std::pair<std::string, const MethodErrors*>>& methods) {
  std::ofstream out(path);
  if (!out) return false;
  out << "method,index,x,y,z,surface,error_deg\n";
  char buffer[256];
  for (const auto& [name, errors] : methods) {
    for (const PointError& e : errors->errors) {
      const Vec3& p = e.position;
      std::snprintf(buffer, sizeof(buffer), "%s,%zu,%.4f,%.4f,%.4f,%s,%.6f\n", name.c_str(),
                    e.index, p.x(), p.y(), p.z(),
                    e.surface == Surface::kGround ? "ground" : "slope", e.error_deg);
      out << buffer;
    }
  }
  return static_cast<bool>(out);
}

int Run(const Options& o) {
  if (!(o.step_deg > 0.0) || !(o.alpha_min_deg >= 0.0) || !(o.alpha_max_deg >= o.alpha_min_deg) ||
      !(o.alpha_max_deg < 90.0)) {
    std::fprintf(stderr, "ovpc_normals_experiment: need 0 <= --alpha-min <= --alpha-max < 90 and "
                         "--step > 0\n");
    return 2;
  }
  bool use_pcl = false;
  bool also_eigen = false;
  if (o.pca == "auto") {
    use_pcl = kHavePcl;
  } else if (o.pca == "pcl" || o.pca == "both") {
    if (!kHavePcl) {
      std::fprintf(stderr, "ovpc_normals_experiment: --pca %s needs PCL; install it with "
                           "scripts/install-deps --with-baselines and re-run cmake\n",
                   o.pca.c_str());
      return 2;
    }
    use_pcl = true;
    also_eigen = o.pca == "both";
  }
  if (o.filter.voxel_size_m < 0.0 || o.filter.min_hits < 1) {
    std::fprintf(stderr,
                 "ovpc_normals_experiment: need --ovpc-voxel >= 0 and --ovpc-min-hits >= 1\n");
    return 2;
  }
  try {
    o.scene.Validate();
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "ovpc_normals_experiment: %s\n", e.what());
    return 2;
  }
  baselines::PcaNormalsConfig pca_config;
  pca_config.radius_m = o.pca_radius_m;
  pca_config.Validate();
  const std::string pca_name = use_pcl ? "pcl::NormalEstimation" : "Eigen PCA (EstimatePcaNormals)";
  NormalEstimator primary = [pca_config](const Points& points, const Vec3& viewpoint) {
    return baselines::EstimatePcaNormals(points, viewpoint, pca_config);
  };
#if defined(OVPC_HAVE_PCL)
  if (use_pcl) {
    primary = [pca_config](const Points& points, const Vec3& viewpoint) {
      return baselines::EstimatePclNormals(points, viewpoint, pca_config);
    };
  }
#endif

  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) {
    std::fprintf(stderr, "ovpc_normals_experiment: cannot create %s: %s\n", o.out_dir.c_str(),
                 ec.message().c_str());
    return 1;
  }

  const int num_alphas =
      static_cast<int>(std::floor((o.alpha_max_deg - o.alpha_min_deg) / o.step_deg + 1e-9)) + 1;
  OvpcMapper::Config mapper_config;
  mapper_config.ghpr.gamma = o.gamma;
  mapper_config.vertex_normals.rule = o.vertex_normals;
  VertexNormals::Config other_normals = mapper_config.vertex_normals;
  other_normals.rule = o.vertex_normals == VertexNormals::Rule::kPlaneFit ? VertexNormals::Rule::kMeanOfFaces
                                                                          : VertexNormals::Rule::kPlaneFit;
  try {
    mapper_config.Validate();
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "ovpc_normals_experiment: %s\n", e.what());
    return 2;
  }
  const OvpcMapper mapper(mapper_config);
  MethodSeries ovpc{"ovpc", "normals_ovpc.csv", {}, 0.0};
  const std::string other_name = "ovpc_" + VertexNormalRuleName(other_normals.rule);
  MethodSeries ovpc_other{other_name, "normals_" + other_name + ".csv", {}, 0.0};
  MethodSeries pca{"pca", "normals_pca.csv", {}, 0.0};
  MethodSeries pca_visible{"pca_visible", "normals_pca_visible.csv", {}, 0.0};
  MethodSeries pca_eigen{"pca_eigen", "normals_pca_eigen.csv", {}, 0.0};
  int ovpc_failures = 0;
  std::size_t points_total = 0;
  std::size_t ovpc_points_total = 0;
  const Clock::time_point start = Clock::now();
  for (int k = 0; k < num_alphas; ++k) {
    // Rounded to 1e-6 deg so that 0.1 deg steps print and compare cleanly.
    const double alpha_deg = std::round((o.alpha_min_deg + k * o.step_deg) * 1e6) / 1e6;
    const std::uint64_t seed = TrialSeed(o.seed, static_cast<std::uint64_t>(k));
    const NormalsTrial trial =
        RunNormalsTrial(alpha_deg, o.scene, mapper, primary, seed, o.filter, &other_normals);
    if (trial.ovpc_status != GhprStatus::kOk) ++ovpc_failures;
    points_total += trial.points;
    ovpc_points_total += trial.ovpc_input_points;
    ovpc.rows.push_back(MakeRow(alpha_deg, trial.ovpc, trial.points, o.unoriented));
    ovpc.total_ms += trial.ovpc.ms;
    ovpc_other.rows.push_back(MakeRow(alpha_deg, trial.ovpc_other, trial.points, o.unoriented));
    ovpc_other.total_ms += trial.ovpc_other.ms;
    pca.rows.push_back(MakeRow(alpha_deg, trial.pca, trial.points, o.unoriented));
    pca.total_ms += trial.pca.ms;
    pca_visible.rows.push_back(MakeRow(alpha_deg, trial.pca_visible, trial.points, o.unoriented));

    const bool dump = !o.points_csv.empty() && std::abs(alpha_deg - o.points_alpha_deg) < 1e-6;
    MethodErrors eigen_errors;
    if (also_eigen || dump) {
      const SlopeScene scene = MakeSlopeScene(DegToRad(alpha_deg), o.scene, seed);
      if (also_eigen) {
        const Clock::time_point t = Clock::now();
        const baselines::PcaNormals normals =
            baselines::EstimatePcaNormals(scene.points, scene.viewpoint, pca_config);
        pca_eigen.total_ms += MsSince(t, Clock::now());
        eigen_errors = PointNormalErrors(scene, normals);
        pca_eigen.rows.push_back(MakeRow(alpha_deg, eigen_errors, trial.points, o.unoriented));
      }
      if (dump) {
        std::vector<std::pair<std::string, const MethodErrors*>> methods = {
            {"ovpc", &trial.ovpc}, {"pca", &trial.pca}};
        if (also_eigen) methods.emplace_back("pca_eigen", &eigen_errors);
        if (!WritePointErrors(o.points_csv, methods)) {
          std::fprintf(stderr, "ovpc_normals_experiment: cannot write %s\n", o.points_csv.c_str());
          return 1;
        }
        std::fprintf(stderr, "wrote per-point errors at alpha %.2f deg to %s\n", alpha_deg,
                     o.points_csv.c_str());
      }
    }
    if (!o.quiet && (k % 10 == 0 || k + 1 == num_alphas)) {
      std::fprintf(stderr,
                   "[%3d/%d] alpha %5.2f deg: %zu points; OVPC %zu visible, mean %.2f deg "
                   "(%.0f ms); PCA mean %.2f deg (%.0f ms)\n",
                   k + 1, num_alphas, alpha_deg, trial.points, trial.ovpc.errors.size(),
                   ovpc.rows.back().stats.mean, trial.ovpc.ms, pca.rows.back().stats.mean,
                   trial.pca.ms);
    }
  }
  const double wall_s = MsSince(start, Clock::now()) / 1000.0;

  std::vector<const MethodSeries*> outputs = {&ovpc, &ovpc_other, &pca, &pca_visible};
  if (also_eigen) outputs.push_back(&pca_eigen);
  int exit_code = 0;
  for (const MethodSeries* series : outputs) {
    const std::string path = (std::filesystem::path(o.out_dir) / series->file).string();
    if (WriteSeries(path, *series)) {
      std::fprintf(stderr, "wrote %s\n", path.c_str());
    } else {
      std::fprintf(stderr, "ovpc_normals_experiment: cannot write %s\n", path.c_str());
      exit_code = 1;
    }
  }

  std::printf("Normal-estimation experiment (paper, \"Evaluation in simulation\")\n");
  std::printf("machine: %s; build: %s\n", MachineName().c_str(), BuildType().c_str());
  std::printf("scene:   %.0f m x %.0f m, slope from x = %.1f m; %d clouds of %.2f m spacing, "
              "+-%.3f m uniform noise per axis, pose error +-%.2f deg / +-%.2f m per axis; "
              "viewpoint %.2f m above the centre\n",
              2 * o.scene.half_extent_m, 2 * o.scene.half_extent_m, o.scene.slope_start_x_m,
              o.scene.num_clouds, o.scene.spacing_m, o.scene.noise_m, o.scene.pose_error_deg,
              o.scene.pose_error_m, o.scene.viewpoint_height_m);
  std::printf("slopes:  %d, alpha %.2f..%.2f deg, step %.2f deg; seed %llu; about %zu points "
              "per slope\n",
              num_alphas, o.alpha_min_deg, o.alpha_max_deg, o.step_deg,
              static_cast<unsigned long long>(o.seed), points_total / num_alphas);
  std::printf("metric:  %s angle between the estimated and the true normal\n",
              o.unoriented ? "UNORIENTED (diagnostic)" : "oriented");
  std::printf("methods: ovpc = OVPC vertex normals (OvpcMapper defaults, gamma %.3g, vertex normals %s, "
              "patch %.2f m / %d points); %s = the same meshes' normals by %s; pca = %s, "
              "radius %.2f m, flipped towards the viewpoint\n",
              mapper.config().ghpr.gamma, VertexNormalRuleName(o.vertex_normals).c_str(), mapper_config.vertex_normals.radius_m,
              mapper_config.vertex_normals.max_patch_points, other_name.c_str(), VertexNormalRuleName(other_normals.rule).c_str(),
              pca_name.c_str(), o.pca_radius_m);
  if (o.filter.voxel_size_m > 0.0) {
    std::printf("OVPC input: VOXEL-FILTERED (diagnostic), %.3f m voxels with >= %d points; "
                "about %zu points per slope\n",
                o.filter.voxel_size_m, o.filter.min_hits, ovpc_points_total / num_alphas);
  }
  std::printf("\n");
  std::printf("%-19s %16s %16s %16s %16s %16s %9s %12s\n", "method", "mean of means", "mean of sds",
              "mean of medians", "mean of p90", "mean of p95", "> 90 deg", "time/slope");
  nlohmann::json summary;
  for (const MethodSeries* series : outputs) {
    const OverAlpha a = Average(*series);
    char time[32] = "-";
    if (series->total_ms > 0.0) {
      std::snprintf(time, sizeof(time), "%.1f ms", series->total_ms / num_alphas);
    }
    std::printf("%-19s %12.3f deg %12.3f deg %12.3f deg %12.3f deg %12.3f deg %8.3f%% %12s\n",
                series->name.c_str(), a.mean_of_means, a.mean_of_sds, a.mean_of_medians, a.mean_of_p90,
                a.mean_of_p95, 100.0 * a.share_over_90, time);
    summary["methods"][series->name] = {{"csv", series->file},
                                        {"mean_of_means_deg", a.mean_of_means},
                                        {"mean_of_sds_deg", a.mean_of_sds},
                                        {"mean_of_medians_deg", a.mean_of_medians},
                                        {"mean_of_p90_deg", a.mean_of_p90},
                                        {"mean_of_p95_deg", a.mean_of_p95},
                                        {"share_over_90", a.share_over_90},
                                        {"total_ms", series->total_ms}};
  }
  std::printf("\npaper: OVPC mean 3.25 deg over all slopes, PCA higher mean and sd\n");
  if (ovpc_failures > 0) {
    std::printf("WARNING: %d OVPC updates did not return ok\n", ovpc_failures);
  }
  std::printf("wall time %.1f s\n", wall_s);

  summary["machine"] = MachineName();
  summary["build"] = BuildType();
  summary["pca_backend"] = pca_name;
  summary["pca_radius_m"] = o.pca_radius_m;
  summary["seed"] = o.seed;
  summary["gamma"] = o.gamma;
  summary["vertex_normals"] = {{"rule", VertexNormalRuleName(o.vertex_normals)},
                               {"other_rule", VertexNormalRuleName(other_normals.rule)},
                               {"radius_m", mapper_config.vertex_normals.radius_m},
                               {"max_patch_points", mapper_config.vertex_normals.max_patch_points},
                               {"other_rule_ms_note", "the other rule's total_ms is BuildTraversabilityCloud alone"}};
  summary["metric"] = o.unoriented ? "unoriented" : "oriented";
  summary["ovpc_voxel_m"] = o.filter.voxel_size_m;
  summary["ovpc_min_hits"] = o.filter.min_hits;
  summary["alpha_min_deg"] = o.alpha_min_deg;
  summary["alpha_max_deg"] = o.alpha_max_deg;
  summary["step_deg"] = o.step_deg;
  summary["slopes"] = num_alphas;
  summary["scene"] = {{"half_extent_m", o.scene.half_extent_m},
                      {"slope_start_x_m", o.scene.slope_start_x_m},
                      {"spacing_m", o.scene.spacing_m},
                      {"noise_m", o.scene.noise_m},
                      {"num_clouds", o.scene.num_clouds},
                      {"pose_error_deg", o.scene.pose_error_deg},
                      {"pose_error_m", o.scene.pose_error_m},
                      {"viewpoint_height_m", o.scene.viewpoint_height_m}};
  summary["ovpc_failures"] = ovpc_failures;
  summary["wall_s"] = wall_s;
  const std::string json_path =
      (std::filesystem::path(o.out_dir) / "normals_summary.json").string();
  std::ofstream json(json_path);
  json << summary.dump(2) << "\n";
  if (!json) {
    std::fprintf(stderr, "ovpc_normals_experiment: cannot write %s\n", json_path.c_str());
    exit_code = 1;
  } else {
    std::fprintf(stderr, "wrote %s\n", json_path.c_str());
  }
  return exit_code;
}

}  // namespace
}  // namespace ovpc::bench

int main(int argc, char** argv) {
  using ovpc::bench::Options;
  Options o;
  CLI::App app{"ovpc_normals_experiment - the paper's normal-estimation experiment: OVPC vertex "
               "normals vs PCA normals on a ground plane and a slope of 0..35 deg"};
  app.add_option("--alpha-min", o.alpha_min_deg, "First slope, degrees")->capture_default_str();
  app.add_option("--alpha-max", o.alpha_max_deg, "Last slope, degrees")->capture_default_str();
  app.add_option("--step", o.step_deg, "Slope step, degrees (paper: 0.1; e.g. 5 for a quick run)")
      ->capture_default_str();
  app.add_option("--seed", o.seed, "Run seed (each slope gets its own seed from it)")
      ->capture_default_str();
  app.add_option("--pca", o.pca,
                 "PCA backend: auto (PCL if built with it, else Eigen), eigen, pcl, or both "
                 "(PCL in normals_pca.csv, Eigen in normals_pca_eigen.csv)")
      ->check(CLI::IsMember({"auto", "eigen", "pcl", "both"}))
      ->capture_default_str();
  app.add_option("--pca-radius", o.pca_radius_m, "PCA neighbourhood radius, m (paper: 0.3)")
      ->capture_default_str();
  app.add_option("--gamma", o.gamma, "GHPR exponential kernel parameter (paper: -0.03)")
      ->capture_default_str();
  app.add_option("--vertex-normals", o.vertex_normals,
                 "Rule of the ovpc series: plane_fit or mean_of_faces (the paper's); the other rule's "
                 "errors on the same meshes are written beside it")
      ->transform(CLI::CheckedTransformer(ovpc::bench::VertexNormalRules()));
  app.add_option("--slope-start", o.scene.slope_start_x_m,
                 "x where the inclined plane starts, m (not given in the paper)")
      ->capture_default_str();
  app.add_option("--out-dir", o.out_dir, "Directory for the CSV and JSON files")
      ->capture_default_str();
  app.add_option("--points-csv", o.points_csv,
                 "Also write every point's error at --points-alpha to this CSV");
  app.add_option("--points-alpha", o.points_alpha_deg, "Slope of the --points-csv dump, degrees");
  app.add_option("--ovpc-voxel", o.filter.voxel_size_m,
                 "Diagnostic: voxel-filter OVPC's input first (the point cloud buffer's filter), "
                 "voxel edge in m; 0 = off (the protocol)")
      ->capture_default_str();
  app.add_option("--ovpc-min-hits", o.filter.min_hits,
                 "Points a voxel needs to be kept with --ovpc-voxel")
      ->capture_default_str();
  app.add_flag("--unoriented", o.unoriented,
               "Diagnostic: score normals as unoriented lines, min(e, 180 - e); n_over_90 still "
               "counts the flipped ones");
  app.add_flag("-q,--quiet", o.quiet, "No progress lines");
  CLI11_PARSE(app, argc, argv);
  try {
    return ovpc::bench::Run(o);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s: %s\n", "ovpc_normals_experiment", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: failed: %s\n", "ovpc_normals_experiment", e.what());
    return 1;
  }
}
