// Map-update benchmark: the OVPC update against a plain GHPR hull (CGAL convex_hull_3 on all
// points) and OctoMap insertPointCloud at 0.1, 0.2 and 0.3 m, on the same generated clouds.
//
// Clouds: MakeBenchClouds({size}, seed, kCloudsPerSize), i.e. MakeOutdoorCloud(size, seed + i):
// a VLP-16 tilted 45 deg on a base spinning at 0.5 Hz, 1.88 m above an outdoor scene (20 deg
// ramp to a plateau, carport roof on posts, poles, trees), 25 scans buffered into one cloud with
// the viewpoint at the origin. Every method sees exactly the same clouds: repetition r uses cloud
// r % kCloudsPerSize.
//
// Timing: std::chrono::steady_clock around the measured call only, the same way for every method.
// Input conversion to a library's own point type (octomap::Pointcloud), the construction of empty
// result objects and the destruction of results happen outside the timed region. The GHPR image
// transform is part of the plain hull path (as it is part of the OVPC update). Each (method,
// size) gets one untimed warm-up run first; a case that would take more than kCaseBudget_s at
// the requested reps gets fewer (the report prints the reps used). Everything runs on one thread.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <future>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/version.h>
#include <octomap/octomap.h>

#include "ovpc/bench/octomap_peer.h"
#include "ovpc/bench/normals_experiment.h"
#include "ovpc/bench/outdoor_clouds.h"
#include "ovpc/bench/report.h"
#include "ovpc/bench/stats.h"
#include "ovpc/core/ovpc_mapper.h"
#include "ovpc/core/point_cloud_buffer.h"
#include "ovpc/synth/synthetic_scene.h"

namespace ovpc::bench {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point_3 = Kernel::Point_3;
using HullMesh = CGAL::Surface_mesh<Point_3>;

constexpr int kDefaultReps = 30;
constexpr int kQuickReps = 3;
constexpr int kCloudsPerSize = 5;
/// Slow cases (OctoMap at 0.1 m traces every ray through ~10 voxels per metre) get fewer reps:
/// as many as the warm-up run's time says fit into this budget, but at least kMinReps.
constexpr double kCaseBudget_s = 30.0;
constexpr int kMinReps = 3;
constexpr double kOctomapResolutions_m[] = {0.1, 0.2, 0.3};

// The clock around each measured call: wall time by default; with --cpu-time the calling thread's
// CPU time, which leaves out time the thread spent preempted on a shared machine (every measured
// method is single-threaded: OvpcMapper, CGAL's hull and Debian's liboctomap, built without OpenMP).
bool g_cpu_time = false;
double NowMs() {
  if (!g_cpu_time) return std::chrono::duration<double, std::milli>(Clock::now().time_since_epoch()).count();
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// --- Command line ------------------------------------------------------------------------------

struct Options {
  int reps = kDefaultReps;
  std::vector<std::size_t> sizes = {6000, 10000, 14000, 50000};
  std::uint64_t seed = 1;
  std::string csv_path;
  std::string json_path;
  bool quick = false;
  int sequence = 200;  // consecutive clouds of a driving vehicle (0: skip)
  int soak = 0;        // map updates for the memory check (0: skip)
  int threads = 1;     // 2: also time the sequence as a two-stage pipeline on two threads
};

void PrintUsage(std::ostream& out) {
  out << "usage: ovpc_bench [--reps N] [--sizes 6000,10000,14000,50000] [--seed S]\n"
         "                  [--csv FILE] [--json FILE] [--sequence N] [--soak N] [--cpu-time]\n"
         "                  [--quick] [--help]\n"
         "  --reps N     timed repetitions per (method, size), default "
      << kDefaultReps
      << "; a case whose warm-up run says\n"
         "               N reps would take over "
      << kCaseBudget_s << " s gets fewer (at least " << kMinReps << ")\n"
         "  --sizes L    comma-separated cloud sizes in points\n"
         "  --seed S     first cloud seed; clouds S .. S+"
      << kCloudsPerSize - 1
      << " are cycled through the reps\n"
         "  --csv FILE   write one row per (method or OVPC stage, size)\n"
         "  --json FILE  write the same as JSON\n"
         "  --sequence N consecutive clouds of a vehicle driving at 1 m/s under the carport, one\n"
         "               update per 20 Hz scan: tail latency (p99/median); default 200, 0 skips\n"
         "  --soak N     N map updates cycling through the sequence's clouds, resident memory\n"
         "               reported every N/10 updates (e.g. 10000); default 0 skips\n"
         "  --threads 2  also run the sequence as a two-stage pipeline on two threads (the hull of\n"
         "               one cloud overlaps the classification and k-d tree of the previous one) and\n"
         "               report the throughput speed-up; the single-core figures stay the target\n"
         "  --cpu-time   time each call by the thread's CPU time instead of the wall clock (robust\n"
         "               when other processes share the machine)\n"
         "  --quick      smoke test: "
      << kQuickReps << " reps, sizes 6000 and 14000 (explicit --reps/--sizes win)\n";
}

bool ParseUnsigned(const std::string& text, std::uint64_t* value) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
  try {
    *value = std::stoull(text);
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

bool ParseSizes(const std::string& text, std::vector<std::size_t>* sizes) {
  sizes->clear();
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    std::uint64_t value = 0;
    if (!ParseUnsigned(item, &value) || value < 4 || value > 10000000) return false;
    sizes->push_back(static_cast<std::size_t>(value));
  }
  return !sizes->empty() && text.back() != ',';
}

/// Returns 0 on success, -1 after --help, 2 on bad arguments (usage printed).
int ParseArgs(int argc, char** argv, Options* options) {
  bool reps_given = false;
  bool sizes_given = false;
  auto bad = [](const std::string& why) {
    std::cerr << "ovpc_bench: " << why << "\n";
    PrintUsage(std::cerr);
    return 2;
  };
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    std::string value;
    bool has_inline_value = false;
    const std::size_t eq = arg.find('=');
    if (arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
      has_inline_value = true;
    }
    auto next_value = [&](std::string* out) {
      if (has_inline_value) {
        *out = value;
        return true;
      }
      if (i + 1 >= argc) return false;
      *out = argv[++i];
      return true;
    };
    if (arg == "--help" || arg == "-h") {
      PrintUsage(std::cout);
      return -1;
    } else if (arg == "--quick" && !has_inline_value) {
      options->quick = true;
    } else if (arg == "--reps") {
      std::uint64_t reps = 0;
      if (!next_value(&value) || !ParseUnsigned(value, &reps) || reps < 1 || reps > 100000) {
        return bad("--reps needs a whole number from 1 to 100000");
      }
      options->reps = static_cast<int>(reps);
      reps_given = true;
    } else if (arg == "--sizes") {
      if (!next_value(&value) || !ParseSizes(value, &options->sizes)) {
        return bad("--sizes needs a comma-separated list of point counts (each >= 4)");
      }
      sizes_given = true;
    } else if (arg == "--seed") {
      std::uint64_t seed = 0;
      if (!next_value(&value) || !ParseUnsigned(value, &seed)) {
        return bad("--seed needs a non-negative whole number");
      }
      options->seed = seed;
    } else if (arg == "--threads") {
      std::uint64_t n = 0;
      if (!next_value(&value) || !ParseUnsigned(value, &n) || n < 1 || n > 2) return bad("--threads needs 1 or 2");
      options->threads = static_cast<int>(n);
    } else if (arg == "--cpu-time" && !has_inline_value) {
      g_cpu_time = true;
    } else if (arg == "--sequence" || arg == "--soak") {
      std::uint64_t count = 0;
      if (!next_value(&value) || !ParseUnsigned(value, &count) || count > 1000000) {
        return bad(arg + " needs a whole number from 0 to 1000000");
      }
      (arg == "--sequence" ? options->sequence : options->soak) = static_cast<int>(count);
    } else if (arg == "--csv") {
      if (!next_value(&options->csv_path) || options->csv_path.empty()) {
        return bad("--csv needs a file name");
      }
    } else if (arg == "--json") {
      if (!next_value(&options->json_path) || options->json_path.empty()) {
        return bad("--json needs a file name");
      }
    } else {
      return bad("unknown argument '" + std::string(argv[i]) + "'");
    }
  }
  if (options->quick) {
    if (!reps_given) options->reps = kQuickReps;
    if (!sizes_given) options->sizes = {6000, 14000};
    options->sequence = std::min(options->sequence, 20);
  }
  return 0;
}

// --- The measured methods ----------------------------------------------------------------------

/// One timed run: the milliseconds of the measured call and a size of its result, for a sanity
/// column (visible points, hull vertices, octree nodes).
struct Run {
  double ms = 0.0;
  std::size_t output = 0;
};

struct OvpcRun {
  Run run;
  StageTimings timings;
  bool ok = false;
  std::string status;
};

OvpcRun RunOvpc(const OvpcMapper& mapper, const Points& points) {
  const double start = NowMs();
  const OvpcMap map = mapper.Update(points, Vec3::Zero());
  const double stop = NowMs();
  OvpcRun result;
  result.run = {stop - start, map.mesh.num_visible()};
  result.timings = map.timings;
  result.ok = map.ok();
  result.status = map.ok() ? "ok" : std::string(StatusName(map.status)) + ": " + map.message;
  return result;
}

/// The plain reference path: GHPR image p |p|^(gamma - 1) of every point, plus the origin, into
/// CGAL's convex_hull_3. Returns the number of hull vertices.
std::size_t GhprHull(const Points& points, double gamma, HullMesh* hull) {
  std::vector<Point_3> images;
  images.reserve(points.size() + 1);
  for (const Vec3& p : points) {
    const double d = p.norm();
    if (!(d > 0.0)) continue;  // a point at the viewpoint has no image
    const double scale = std::pow(d, gamma - 1.0);
    images.emplace_back(p.x() * scale, p.y() * scale, p.z() * scale);
  }
  images.emplace_back(0.0, 0.0, 0.0);
  CGAL::convex_hull_3(images.begin(), images.end(), *hull);
  return hull->number_of_vertices();
}

Run RunPlainHull(const Points& points, double gamma) {
  auto hull = std::make_unique<HullMesh>();
  const double start = NowMs();
  const std::size_t num_vertices = GhprHull(points, gamma, hull.get());
  const double stop = NowMs();
  return {stop - start, num_vertices};
}

Run RunOctomap(const octomap::Pointcloud& cloud, double resolution_m) {
  // Timed here rather than by InsertIntoFreshOctree so that --cpu-time applies to OctoMap too.
  auto tree = std::make_unique<octomap::OcTree>(resolution_m);
  const double start = NowMs();
  tree->insertPointCloud(cloud, octomap::point3d(0.0f, 0.0f, 0.0f));
  const double stop = NowMs();
  return {stop - start, tree->size()};
}

// --- Results -----------------------------------------------------------------------------------

struct Row {
  std::size_t size = 0;
  std::string method;  ///< "ovpc", "cgal_hull", "octomap_0.1", ... or "ovpc.<stage>"
  bool is_stage = false;
  SampleStats stats;
  double ratio = 0.0;        ///< median / median of the OVPC update (wall clock) at this size
  std::size_t output = 0;    ///< result size on the first cloud (see Run::output)
  std::string output_what;   ///< what `output` counts
};

/// The vertex-normal rule other than the library default's, and a mapper with it (the rest default).
OvpcMapper::Config OtherNormalsConfig() {
  OvpcMapper::Config config;
  config.vertex_normals.rule = config.vertex_normals.rule == VertexNormals::Rule::kPlaneFit
                                   ? VertexNormals::Rule::kMeanOfFaces
                                   : VertexNormals::Rule::kPlaneFit;
  return config;
}

/// Per size: the update and its vertex_cloud stage (vertex normals, flags, k-d tree) under the
/// default rule and the other one, medians in ms.
struct NormalsCost {
  std::size_t size = 0;
  double update_ms = 0.0, stage_ms = 0.0;
  double other_update_ms = 0.0, other_stage_ms = 0.0;
};

std::string OctomapName(double resolution_m) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "octomap_%.1f", resolution_m);
  return buffer;
}

bool WriteCsv(const std::string& path, const std::vector<Row>& rows) {
  std::ofstream out(path);
  if (!out) return false;
  out << "size,method,kind,reps,median_ms,p90_ms,p99_ms,mean_ms,sd_ms,min_ms,max_ms,"
         "ratio_to_ovpc,output,output_what\n";
  char buffer[512];
  for (const Row& r : rows) {
    std::snprintf(buffer, sizeof(buffer),
                  "%zu,%s,%s,%d,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%zu,", r.size,
                  CsvField(r.method).c_str(), r.is_stage ? "stage" : "method",
                  static_cast<int>(r.stats.n), r.stats.median, r.stats.p90, r.stats.p99,
                  r.stats.mean, r.stats.sd, r.stats.min, r.stats.max, r.ratio, r.output);
    out << buffer << CsvField(r.output_what) << "\n";
  }
  return static_cast<bool>(out);
}

bool WriteJson(const std::string& path, const Options& options, const std::string& machine,
               const std::string& build, const std::vector<Row>& rows) {
  std::ofstream out(path);
  if (!out) return false;
  out << "{\n  \"machine\": \"" << JsonEscape(machine) << "\",\n"
      << "  \"build\": \"" << JsonEscape(build) << "\",\n"
      << "  \"cgal_version\": \"" << CGAL_VERSION_STR << "\",\n"
      << "  \"seed\": " << options.seed << ",\n"
      << "  \"clouds_per_size\": " << kCloudsPerSize << ",\n"
      << "  \"reps\": " << options.reps << ",\n"
      << "  \"results\": [\n";
  char buffer[640];
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    std::snprintf(buffer, sizeof(buffer),
                  "    {\"size\": %zu, \"method\": \"%s\", \"kind\": \"%s\", \"reps\": %d, "
                  "\"median_ms\": %.6f, \"p90_ms\": %.6f, \"p99_ms\": %.6f, \"mean_ms\": %.6f, "
                  "\"sd_ms\": %.6f, \"min_ms\": %.6f, \"max_ms\": %.6f, \"ratio_to_ovpc\": %.6f, "
                  "\"output\": %zu, \"output_what\": \"%s\"}%s\n",
                  r.size, JsonEscape(r.method).c_str(), r.is_stage ? "stage" : "method",
                  static_cast<int>(r.stats.n), r.stats.median, r.stats.p90, r.stats.p99,
                  r.stats.mean, r.stats.sd, r.stats.min, r.stats.max, r.ratio,
                  r.output, JsonEscape(r.output_what).c_str(), i + 1 < rows.size() ? "," : "");
    out << buffer;
  }
  out << "  ]\n}\n";
  return static_cast<bool>(out);
}

// --- Driver ------------------------------------------------------------------------------------

/// Runs `measure` once untimed on cloud 0, then up to `max_reps` times cycling through the clouds
/// (fewer when the warm-up run says they would exceed kCaseBudget_s; at least kMinReps).
std::vector<Run> Repeat(int max_reps, const std::function<Run(int cloud)>& measure) {
  const double warm_up_ms = measure(0).ms;
  int reps = max_reps;
  if (warm_up_ms * max_reps > kCaseBudget_s * 1000.0) {
    reps = std::max(kMinReps, static_cast<int>(kCaseBudget_s * 1000.0 / warm_up_ms));
    reps = std::min(reps, max_reps);
  }
  std::vector<Run> runs;
  runs.reserve(static_cast<std::size_t>(reps));
  for (int r = 0; r < reps; ++r) runs.push_back(measure(r % kCloudsPerSize));
  return runs;
}

std::vector<double> Millis(const std::vector<Run>& runs) {
  std::vector<double> ms;
  ms.reserve(runs.size());
  for (const Run& run : runs) ms.push_back(run.ms);
  return ms;
}

void ReportProgress(std::size_t size, const std::string& method, const SampleStats& stats) {
  std::fprintf(stderr, "[%6zu] %-14s %3d reps  median %9.2f ms\n", size, method.c_str(),
               static_cast<int>(stats.n), stats.median);
}

// --- Sequence: tail latency and memory over consecutive clouds -------------------------------

long ResidentKb(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field, 0) == 0) return std::atol(line.c_str() + std::strlen(field));
  }
  return -1;
}

// A vehicle drives at 1 m/s along +y from (0, -8) through the carport; every 20 Hz scan goes into the
// point cloud buffer (25 scans, 14,000 points) and the map is updated from the buffer.
std::vector<Points> SequenceClouds(int frames, std::uint64_t seed) {
  const synth::Scene scene = synth::MakeOutdoorScene(seed);
  const SpinningLidarMount mount;
  PointCloudBuffer buffer;
  std::vector<Points> clouds;
  const int warmup = buffer.config().max_scans - 1;
  for (int k = 0; k < frames + warmup; ++k) {
    const double t_s = k / mount.scan_hz;
    Eigen::Isometry3d T_O_B = Eigen::Isometry3d::Identity();
    T_O_B.translation() = Vec3(0.0, -8.0 + 1.0 * t_s, 0.0);
    T_O_B.linear() = Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()).toRotationMatrix();
    for (Scan& scan : synth::SimulateScans(scene, mount, T_O_B, t_s, 1, 0.015, seed * 100000 + k)) {
      buffer.Push(std::move(scan));
    }
    if (k >= warmup) clouds.push_back(buffer.Build().points_L);
  }
  return clouds;
}

void RunSequence(const Options& options, std::vector<Row>* rows) {
  std::fprintf(stderr, "[sequence] simulating %d consecutive clouds\n", options.sequence);
  const std::vector<Points> clouds = SequenceClouds(options.sequence, options.seed);
  const OvpcMapper mapper;
  OvpcMapper::Config reference_config;
  reference_config.ghpr.reference_hull = true;
  const OvpcMapper reference(reference_config);
  const OvpcMapper other(OtherNormalsConfig());
  std::vector<double> fast_ms, reference_ms, other_ms;
  std::size_t min_points = SIZE_MAX, max_points = 0, failures = 0;
  RunOvpc(mapper, clouds.front());  // warm-up
  for (const Points& cloud : clouds) {
    min_points = std::min(min_points, cloud.size());
    max_points = std::max(max_points, cloud.size());
    const OvpcRun run = RunOvpc(mapper, cloud);
    failures += run.ok ? 0 : 1;
    fast_ms.push_back(run.run.ms);
    reference_ms.push_back(RunOvpc(reference, cloud).run.ms);
    other_ms.push_back(RunOvpc(other, cloud).run.ms);
  }
  const SampleStats fast = Summarize(fast_ms), ref = Summarize(reference_ms), alt = Summarize(other_ms);
  std::printf("\nSequence: %zu consecutive clouds (%zu..%zu points), one update per scan\n", clouds.size(),
              min_points, max_points);
  std::printf("  %-22s median %7.3f  p90 %7.3f  p99 %7.3f  max %7.3f ms  p99/median %.2f%s\n", "ovpc",
              fast.median, fast.p90, fast.p99, fast.max, fast.p99 / fast.median,
              failures ? "  (some updates failed)" : "");
  std::printf("  %-22s median %7.3f  p90 %7.3f  p99 %7.3f  max %7.3f ms  p99/median %.2f\n",
              "ovpc (CGAL quickhull)", ref.median, ref.p90, ref.p99, ref.max, ref.p99 / ref.median);
  const std::string other_name = "ovpc (" + VertexNormalRuleName(other.config().vertex_normals.rule) + ")";
  std::printf("  %-22s median %7.3f  p90 %7.3f  p99 %7.3f  max %7.3f ms  p99/median %.2f  (ovpc / this: %.2fx)\n",
              other_name.c_str(), alt.median, alt.p90, alt.p99, alt.max, alt.p99 / alt.median, fast.median / alt.median);
  rows->push_back(Row{max_points, "sequence.ovpc", false, fast, 1.0, clouds.size(), "clouds"});
  rows->push_back(Row{max_points, "sequence.ovpc_cgal_hull", false, ref, ref.median / fast.median,
                      clouds.size(), "clouds"});
  rows->push_back(Row{max_points, "sequence.ovpc_" + VertexNormalRuleName(other.config().vertex_normals.rule), false, alt,
                      alt.median / fast.median, clouds.size(), "clouds"});

  if (options.threads == 2) {
    // Throughput per cloud, wall clock: the same two stages one after the other, then pipelined.
    const Ghpr::Config ghpr;
    const Traversability::Config traversability;
    auto classify = [&](GhprResult r) {
      ClassifyFaces(traversability, &r.mesh);
      return BuildTraversabilityCloud(r.mesh).size();
    };
    std::size_t check_serial = 0, check_pipelined = 0;
    auto t0 = Clock::now();
    for (const Points& cloud : clouds) check_serial += classify(ComputeGhpr(cloud, Vec3::Zero(), ghpr));
    const double serial_ms = MsSince(t0, Clock::now()) / clouds.size();
    t0 = Clock::now();
    std::future<std::size_t> pending;
    for (const Points& cloud : clouds) {
      GhprResult r = ComputeGhpr(cloud, Vec3::Zero(), ghpr);  // hulls stay on this thread (per-thread buffers)
      if (pending.valid()) check_pipelined += pending.get();
      pending = std::async(std::launch::async, classify, std::move(r));
    }
    if (pending.valid()) check_pipelined += pending.get();
    const double pipelined_ms = MsSince(t0, Clock::now()) / clouds.size();
    std::printf("  two threads (pipeline): %.3f ms per cloud against %.3f ms on one thread: %.2fx throughput%s\n",
                pipelined_ms, serial_ms, serial_ms / pipelined_ms,
                check_serial == check_pipelined ? "" : "  (RESULTS DIFFER)");
  }

  if (options.soak <= 0) return;
  std::printf("\nSoak: %d updates cycling through the sequence, resident memory (VmRSS):\n", options.soak);
  const int every = std::max(1, options.soak / 10);
  for (int i = 0; i < options.soak; ++i) {
    const OvpcMap map = mapper.Update(clouds[static_cast<std::size_t>(i) % clouds.size()], Vec3::Zero());
    if ((i + 1) % every == 0) {
      std::printf("  after %6d updates: %ld kB (peak %ld kB)\n", i + 1, ResidentKb("VmRSS:"), ResidentKb("VmHWM:"));
      std::fflush(stdout);
    }
  }
}

int Main(int argc, char** argv) {
  Options options;
  const int parse = ParseArgs(argc, argv, &options);
  if (parse == -1) return 0;
  if (parse != 0) return parse;

  const std::string machine = MachineName();
  const std::string build = BuildType();
  const OvpcMapper mapper;
  const double gamma = mapper.config().ghpr.gamma;
  const Clock::time_point bench_start = Clock::now();

  const OvpcMapper other_mapper(OtherNormalsConfig());
  const std::string rule_name = VertexNormalRuleName(mapper.config().vertex_normals.rule);
  const std::string other_name = "ovpc_" + VertexNormalRuleName(other_mapper.config().vertex_normals.rule);
  std::vector<NormalsCost> normals_costs;
  std::vector<Row> rows;
  int ovpc_failures = 0;
  std::string first_failure;
  for (const std::size_t size : options.sizes) {
    std::fprintf(stderr, "[%6zu] generating %d clouds (seeds %llu..%llu)\n", size, kCloudsPerSize,
                 static_cast<unsigned long long>(options.seed),
                 static_cast<unsigned long long>(options.seed + kCloudsPerSize - 1));
    std::vector<Points> clouds;
    std::vector<octomap::Pointcloud> octo_clouds;
    for (BenchCloud& cloud : MakeBenchClouds({size}, options.seed, kCloudsPerSize)) {
      clouds.push_back(std::move(cloud.points));
      octo_clouds.push_back(ToOctomap(clouds.back()));
      if (clouds.back().size() != size) {
        std::fprintf(stderr, "[%6zu] note: cloud %zu has %zu points\n", size, clouds.size() - 1,
                     clouds.back().size());
      }
    }

    // OVPC update: the wall clock of Update(), and its own per-stage timings.
    std::vector<OvpcRun> ovpc_results;
    const std::vector<Run> ovpc_runs = Repeat(options.reps, [&](int cloud) {
      ovpc_results.push_back(RunOvpc(mapper, clouds[cloud]));
      return ovpc_results.back().run;
    });
    ovpc_results.erase(ovpc_results.begin());  // the warm-up run
    for (const OvpcRun& result : ovpc_results) {
      if (result.ok) continue;
      ++ovpc_failures;
      if (first_failure.empty()) first_failure = result.status;
    }
    Row ovpc_row{size, "ovpc", false, Summarize(Millis(ovpc_runs)), 1.0,
                 ovpc_runs.front().output, "visible points"};
    const double ovpc_median_ms = ovpc_row.stats.median;
    ReportProgress(size, "ovpc", ovpc_row.stats);
    rows.push_back(ovpc_row);

    const std::vector<std::pair<std::string, double StageTimings::*>> stages = {
        {"sanitize", &StageTimings::sanitize_ms},
        {"transform", &StageTimings::transform_ms},
        {"hull", &StageTimings::hull_ms},
        {"mesh", &StageTimings::mesh_ms},
        {"traversability", &StageTimings::traversability_ms},
        {"vertex_cloud", &StageTimings::vertex_cloud_ms},
        {"total", &StageTimings::total_ms}};
    for (const auto& [name, member] : stages) {
      std::vector<double> ms;
      for (const OvpcRun& result : ovpc_results) ms.push_back(result.timings.*member);
      Row row{size, "ovpc." + name, true, Summarize(ms), 0.0, 0, ""};
      row.ratio = ovpc_median_ms > 0.0 ? row.stats.median / ovpc_median_ms : 0.0;
      rows.push_back(row);
    }

    auto add_method = [&](const std::string& name, const std::string& output_what,
                          const std::function<Run(int)>& measure) {
      const std::vector<Run> runs = Repeat(options.reps, measure);
      Row row{size, name, false, Summarize(Millis(runs)), 0.0, runs.front().output,
              output_what};
      row.ratio = ovpc_median_ms > 0.0 ? row.stats.median / ovpc_median_ms : 0.0;
      ReportProgress(size, name, row.stats);
      rows.push_back(row);
    };
    // The other vertex-normal rule on the same clouds: the whole update and its vertex_cloud stage.
    std::vector<OvpcRun> other_results;
    add_method(other_name, "visible points", [&](int cloud) {
      other_results.push_back(RunOvpc(other_mapper, clouds[cloud]));
      return other_results.back().run;
    });
    other_results.erase(other_results.begin());  // the warm-up run
    std::vector<double> stage_ms, other_stage_ms;
    for (const OvpcRun& result : ovpc_results) stage_ms.push_back(result.timings.vertex_cloud_ms);
    for (const OvpcRun& result : other_results) other_stage_ms.push_back(result.timings.vertex_cloud_ms);
    normals_costs.push_back({size, ovpc_median_ms, Summarize(stage_ms).median, rows.back().stats.median,
                             Summarize(other_stage_ms).median});
    OvpcMapper::Config reference_config;
    reference_config.ghpr.reference_hull = true;
    const OvpcMapper reference(reference_config);
    add_method("ovpc_cgalhull", "visible points",
               [&](int cloud) { return RunOvpc(reference, clouds[cloud]).run; });
    add_method("cgal_hull", "hull vertices",
               [&](int cloud) { return RunPlainHull(clouds[cloud], gamma); });
    for (const double res_m : kOctomapResolutions_m) {
      add_method(OctomapName(res_m), "octree nodes",
                 [&](int cloud) { return RunOctomap(octo_clouds[cloud], res_m); });
    }
  }
  const double bench_s = MsSince(bench_start, Clock::now()) / 1000.0;

  // --- Report ---
  std::printf("OVPC map update benchmark\n");
  std::printf("machine: %s\n", machine.c_str());
  std::printf("build:   %s; %s; CGAL %s; OctoMap (liboctomap) single-threaded\n", build.c_str(),
              __VERSION__, CGAL_VERSION_STR);
  std::printf("clouds:  %d per size, MakeOutdoorCloud(size, seed %llu..%llu), cycled through the "
              "reps; viewpoint at the origin\n",
              kCloudsPerSize, static_cast<unsigned long long>(options.seed),
              static_cast<unsigned long long>(options.seed + kCloudsPerSize - 1));
  std::printf("timing:  %s around the measured call; 1 untimed warm-up per case; "
              "reps %d (fewer if over %.0f s per case); ratio = median / OVPC median\n",
              g_cpu_time ? "thread CPU time" : "steady_clock (wall)", options.reps, kCaseBudget_s);
  std::printf("methods: ovpc = OvpcMapper::Update (gamma %.3g, vertex normals %s); %s = the same with the other\n"
              "         vertex-normal rule; ovpc_cgalhull = the same as ovpc with CGAL's quickhull\n"
              "         (Ghpr::Config::reference_hull); cgal_hull = plain path: GHPR transform + "
              "CGAL convex_hull_3 on all points;\n"
              "         octomap_R = fresh OcTree(R), insertPointCloud from the origin, no max "
              "range\n\n",
              gamma, rule_name.c_str(), other_name.c_str());
  std::printf("%7s  %-18s %5s %10s %10s %10s %10s %9s  %-14s %s\n", "size", "method", "reps",
              "median_ms", "p90_ms", "p99_ms", "mean_ms", "sd_ms", "vs OVPC", "output");
  std::size_t last_size = 0;
  for (const Row& r : rows) {
    if (r.is_stage) continue;
    if (r.size != last_size && last_size != 0) std::printf("\n");
    last_size = r.size;
    char ratio[32];
    std::snprintf(ratio, sizeof(ratio), "%.2fx", r.ratio);
    std::printf("%7zu  %-18s %5d %10.3f %10.3f %10.3f %10.3f %9.3f  %-14s %zu %s\n", r.size,
                r.method.c_str(), static_cast<int>(r.stats.n), r.stats.median, r.stats.p90,
                r.stats.p99, r.stats.mean, r.stats.sd, ratio, r.output,
                r.output_what.c_str());
  }

  std::printf("\nOVPC stage medians, ms (share of the OVPC median wall clock):\n");
  std::printf("%7s %16s %16s %16s %16s %16s %16s %16s\n", "size", "sanitize", "transform", "hull",
              "mesh", "traversability", "vertex_cloud", "total(internal)");
  for (const std::size_t size : options.sizes) {
    std::printf("%7zu", size);
    for (const Row& r : rows) {
      if (r.size != size || !r.is_stage) continue;
      char cell[40];
      std::snprintf(cell, sizeof(cell), "%.3f (%.0f%%)", r.stats.median, 100.0 * r.ratio);
      std::printf(" %16s", cell);
    }
    std::printf("\n");
  }

  std::printf("\nSummary (median vs OVPC median):\n");
  for (const std::size_t size : options.sizes) {
    std::printf("%7zu:", size);
    for (const Row& r : rows) {
      if (r.size != size || r.is_stage || r.method == "ovpc") continue;
      std::printf("  %s = %.2fx OVPC", r.method.c_str(), r.ratio);
    }
    std::printf("\n");
  }
  std::printf("\nVertex normals, medians in ms: the update and its vertex_cloud stage (normals, flags, k-d tree)\n");
  std::printf("%7s %14s %14s %14s %14s %9s\n", "size", ("ovpc " + rule_name).c_str(), "stage",
              other_name.c_str(), "stage", "ratio");
  for (const NormalsCost& c : normals_costs) {
    std::printf("%7zu %14.3f %14.3f %14.3f %14.3f %8.2fx\n", c.size, c.update_ms, c.stage_ms, c.other_update_ms,
                c.other_stage_ms, c.other_update_ms > 0.0 ? c.update_ms / c.other_update_ms : 0.0);
  }
  std::printf("(ratio: the ovpc update's median over the %s update's)\n", other_name.c_str());
  if (ovpc_failures > 0) {
    std::printf("\nWARNING: %d OVPC updates did not return ok (first: %s)\n", ovpc_failures,
                first_failure.c_str());
  }
  if (options.sequence > 0) RunSequence(options, &rows);
  std::printf("\nbenchmark wall time %.1f s (sizes), %.1f s (all)\n", bench_s,
              MsSince(bench_start, Clock::now()) / 1000.0);

  int exit_code = 0;
  if (!options.csv_path.empty()) {
    if (WriteCsv(options.csv_path, rows)) {
      std::fprintf(stderr, "wrote %s\n", options.csv_path.c_str());
    } else {
      std::fprintf(stderr, "ovpc_bench: cannot write %s\n", options.csv_path.c_str());
      exit_code = 1;
    }
  }
  if (!options.json_path.empty()) {
    if (WriteJson(options.json_path, options, machine, build, rows)) {
      std::fprintf(stderr, "wrote %s\n", options.json_path.c_str());
    } else {
      std::fprintf(stderr, "ovpc_bench: cannot write %s\n", options.json_path.c_str());
      exit_code = 1;
    }
  }
  return exit_code;
}

}  // namespace
}  // namespace ovpc::bench

int main(int argc, char** argv) { return ovpc::bench::Main(argc, argv); }
