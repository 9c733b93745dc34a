// End-to-end tests of the `ovpc` command line: exit codes, messages and output files.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <utility>
#include <sstream>
#include <string>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../support/test_clouds.h"
#include "../support/test_scenarios.h"
#include "ovpc/io/cloud_io.h"
#include "ovpc/synth/synthetic_scene.h"

namespace ovpc {
namespace {

namespace fs = std::filesystem;

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ovpc_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  RunResult Run(const std::string& args) const {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = std::string(OVPC_CLI_PATH) + " " + args + " >" + out.string() + " 2>" + err.string();
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = ReadAll(out);
    r.err = ReadAll(err);
    return r;
  }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  void WriteText(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
  // A LiDAR-like .bin: `n` points on a half sphere of radius 5-25 m around the origin, `fields`
  // float32 per record (x, y, z, intensity in [0, 1], and for 5 fields the ring 0-31).
  void WriteBin(const std::string& name, int fields, int n) const {
    std::ofstream out(dir_ / name, std::ios::binary);
    for (int i = 0; i < n; ++i) {
      const double az = 0.37 * i, el = -0.4 + 0.8 * ((i * 7919) % 997) / 997.0, r = 5.0 + (i % 200) * 0.1;
      const float rec[5] = {static_cast<float>(r * std::cos(el) * std::cos(az)), static_cast<float>(r * std::cos(el) * std::sin(az)),
                            static_cast<float>(r * std::sin(el)), static_cast<float>((i % 100) / 100.0), static_cast<float>(i % 32)};
      out.write(reinterpret_cast<const char*>(rec), fields * sizeof(float));
    }
  }

  fs::path dir_;
};

int CountLines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST_F(CliTest, MeshesAGeneratedCloudAndWritesEveryOutput) {
  Points cloud = synth::MakeOutdoorCloud(6000, 2);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  cloud.emplace_back(nan, 1.0, 1.0);
  cloud.emplace_back(0.0, 0.0, 0.0);  // at the viewpoint
  WriteCloudPly(Path("cloud.ply"), cloud);
  const RunResult r = Run("mesh " + Path("cloud.ply") + " --viewpoint 0,0,0 --out " + Path("mesh.ply") +
                          " --points " + Path("points.ply") + " --json " + Path("stats.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("watertight         yes"), std::string::npos) << r.out;
  const auto stats = nlohmann::json::parse(ReadAll(Path("stats.json")));
  EXPECT_EQ(stats["input_points"], 6002);
  EXPECT_EQ(stats["dropped_non_finite"], 1);
  EXPECT_EQ(stats["dropped_at_viewpoint"], 1);
  EXPECT_EQ(stats["points_after_filtering"], 6000);
  EXPECT_EQ(stats["watertight"], true);
  EXPECT_GT(stats["visible_points"].get<int>(), 1000);
  EXPECT_LT(stats["visible_points"].get<int>(), 6000);
  EXPECT_GT(stats["traversable_face_fraction"].get<double>(), 0.1);
  EXPECT_GT(stats["ms"]["total"].get<double>(), 0.0);
  // The outputs open as PLY again: the vertex cloud has one point per visible point.
  EXPECT_EQ(ReadCloud(Path("points.ply")).size(), stats["visible_points"].get<std::size_t>());
  EXPECT_GE(ReadCloud(Path("mesh.ply")).size(), stats["visible_points"].get<std::size_t>());
}

TEST_F(CliTest, BufferStageDropsSingleHitVoxels) {
  Points cloud = testing::Grid(-4.975, 4.975, -4.975, 4.975, 0.0, 0.05);  // 4 hits per 0.1 m voxel
  cloud.emplace_back(3.33, 3.33, 1.77);                    // lone outlier
  WriteCloudPly(Path("cloud.ply"), cloud);
  const RunResult r = Run("mesh " + Path("cloud.ply") + " --viewpoint 0,0,1.88 --voxel 0.1 --min-hits 2 --json " +
                          Path("stats.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto stats = nlohmann::json::parse(ReadAll(Path("stats.json")));
  EXPECT_EQ(stats["buffer"]["dropped_sparse_voxels"], 1);
  EXPECT_EQ(stats["points_after_filtering"], stats["buffer"]["voxels_kept"]);
}

TEST_F(CliTest, LinearKernelRuns) {
  WriteCloudPly(Path("room.ply"), testing::BoxRoom(Vec3(3, 2, 1.5), 0.5));
  const RunResult r = Run("mesh " + Path("room.ply") + " --viewpoint 0.3,-0.2,0.1 --kernel linear -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
}

TEST_F(CliTest, BadInputGivesOneLineAndExitCode2) {
  WriteCloudPly(Path("three.ply"), {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)});
  WriteCloudPly(Path("plane.ply"), testing::Grid(-2, 2, -2, 2, 0.0, 0.5));
  WriteCloudPly(Path("room.ply"), testing::BoxRoom(Vec3(3, 2, 1.5), 0.5));
  WriteText("garbage.ply", "this is not a ply file\n");
  WriteText("cloud.obj", "v 1 2 3\n");
  WriteText("short.xyz", "1 2 3\n4 5\n");
  const std::string missing = Path("does_not_exist.pcd");
  struct Case {
    std::string args;
    std::string expect;  // a piece of the message
  } cases[] = {
      {"mesh " + missing + " --viewpoint 0,0,0", "does_not_exist.pcd"},
      {"mesh " + Path("cloud.obj") + " --viewpoint 0,0,0", "format"},
      {"mesh " + Path("garbage.ply") + " --viewpoint 0,0,0", "garbage.ply"},
      {"mesh " + Path("short.xyz") + " --viewpoint 0,0,0", "short.xyz"},
      {"mesh " + Path("three.ply") + " --viewpoint 0,0,0", "at least 4"},
      {"mesh " + Path("plane.ply") + " --viewpoint 0,0,0", "plane"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --gamma 0.5", "gamma"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --kernel linear --gamma -1", "gamma"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --kernel linear --gamma 2", "gamma"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0", "--viewpoint"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --kernel cubic", "kernel"},
      {"mesh " + Path("room.ply"), "viewpoint"},
      {"fly", "fly"},
      // Parameters that used to take minutes or not finish.
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --gamma -300", "gamma in [-1, 0)"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --kernel linear --gamma 1e160", "at most 1e7"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --max-points -1", "--max-points must be >= 0"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --bin-fields 6", "--bin-fields"},
      {"mesh " + Path("room.ply") + " --viewpoint 0,0,0 --min-range -1", "--min-range"},
      // Files that would block or never end, and a .bin read with the wrong record layout.
      {"mesh " + Path("fifo.xyz") + " --viewpoint 0,0,0", "not a regular file"},
      {"mesh " + Path("zero.bin") + " --viewpoint 0,0,0", "not a regular file"},
      {"mesh " + Path("nuscenes.bin") + " --viewpoint 0,0,0", "wrong --bin-fields"},
      {"mesh " + Path("kitti.bin") + " --viewpoint 0,0,0 --bin-fields 5", "wrong --bin-fields"},
      // The map backend.
      {"run " + missing + " --map voxels", "--map must be ovpc, octomap or elevation, got 'voxels'"},
      {"suite " + missing + " --map voxels", "--map must be ovpc, octomap or elevation, got 'voxels'"},
      {"suite " + missing + " --map octomap --sweep navigator.map=ovpc,elevation", "give one"},
  };
  ASSERT_EQ(::mkfifo(Path("fifo.xyz").c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", Path("zero.bin"));
  WriteBin("nuscenes.bin", 5, 4000);  // 80,000 bytes: a multiple of 16 as well
  WriteBin("kitti.bin", 4, 5000);     // 80,000 bytes: a multiple of 20 as well
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const RunResult r = Run(c.args);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(CountLines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
  }
}

// The layouts are told apart, and read right with the right --bin-fields.
TEST_F(CliTest, BinFilesAreReadWithTheirRecordLayout) {
  WriteBin("kitti.bin", 4, 5000);
  WriteBin("nuscenes.bin", 5, 4000);
  const RunResult kitti = Run("mesh " + Path("kitti.bin") + " --viewpoint 0,0,0 -q --json " + Path("k.json"));
  ASSERT_EQ(kitti.exit_code, 0) << kitti.err;
  EXPECT_EQ(nlohmann::json::parse(ReadAll(Path("k.json")))["input_points"], 5000);
  const RunResult nuscenes =
      Run("mesh " + Path("nuscenes.bin") + " --bin-fields 5 --viewpoint 0,0,0 -q --json " + Path("n.json"));
  ASSERT_EQ(nuscenes.exit_code, 0) << nuscenes.err;
  EXPECT_EQ(nlohmann::json::parse(ReadAll(Path("n.json")))["input_points"], 4000);
}

TEST_F(CliTest, HelpDescribesDroppedPoints) {
  const RunResult r = Run("mesh --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("NaN/inf"), std::string::npos);
  EXPECT_NE(r.out.find("--viewpoint"), std::string::npos);
}

TEST_F(CliTest, BundledSampleCloudMeshes) {
  const std::string sample = std::string(OVPC_SOURCE_DIR) + "/apps/samples/outdoor_14k.ply";
  const RunResult r = Run("mesh " + sample + " --viewpoint 0,0,0 -q --json " + Path("stats.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto stats = nlohmann::json::parse(ReadAll(Path("stats.json")));
  EXPECT_EQ(stats["input_points"], 14000);
  EXPECT_EQ(stats["watertight"], true);
}

// `ovpc suite` end to end on a short flat scenario: a sweep of two speeds, two seeds from
// --first-seed, in two parallel processes; a run that cannot make its deadline fails the suite.
TEST_F(CliTest, SuiteRunsTheSweepAndSeedsAndWritesJUnitAndSummary) {
  WriteText("short.yaml", testing::kShortFlatScenario);
  const RunResult r = Run("suite " + Path("short.yaml") + " --jobs 2 --seeds 2 --first-seed 4 --sweep navigator.follower.target_speed_mps=1.5,2.0 --out " +
                          Path("suite"));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* settings : {"short_flat__navigator.follower.target_speed_mps=1.5", "short_flat__navigator.follower.target_speed_mps=2.0"}) {
    for (const char* seed : {"seed_4", "seed_5"}) {
      EXPECT_TRUE(fs::exists(fs::path(Path("suite")) / settings / seed / "result.json")) << settings << " " << seed;
    }
    EXPECT_FALSE(fs::exists(fs::path(Path("suite")) / settings / "seed_1"));
  }
  const nlohmann::json summary = nlohmann::json::parse(ReadAll(Path("suite/summary.json")));
  const std::string junit = ReadAll(Path("suite/junit.xml"));
  EXPECT_NE(junit.find("<testsuite"), std::string::npos);
  EXPECT_NE(junit.find("tests=\"4\""), std::string::npos) << junit;
  EXPECT_NE(r.out.find("4 of 4 runs passed"), std::string::npos) << r.out;
  // Several seeds: a line per scenario and settings with the pass rate.
  EXPECT_NE(r.out.find("failed seeds"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  2/2 "), std::string::npos) << r.out;
  EXPECT_NE(summary.dump().find("\"seed\":5"), std::string::npos);

  // A bad value in the first combination is an error of that combination; the others still run.
  const RunResult late = Run("suite " + Path("short.yaml") + " --sweep criteria.max_time_s=soon,1 --out " + Path("late"));
  EXPECT_EQ(late.exit_code, 2) << late.out << late.err;
  EXPECT_NE(late.out.find("0 of 2 runs passed"), std::string::npos) << late.out;
  const nlohmann::json late_summary = nlohmann::json::parse(ReadAll(Path("late/summary.json")));
  EXPECT_EQ(late_summary["errors"], 1);
  EXPECT_EQ(late_summary["runs"][0]["settings"][0], "criteria.max_time_s=soon");
  EXPECT_EQ(late_summary["runs"][1]["result"]["passed"], false) << "the run with max_time_s=1 ran and failed";
  EXPECT_EQ(Run("suite " + Path("short.yaml") + " --first-seed -1").exit_code, 2);
}

// The robot's configuration of a run: printed, recorded in result.json, and taken from a preset.
TEST_F(CliTest, RunPrintsRecordsAndTakesTheConfiguration) {
  WriteText("short.yaml", testing::kShortFlatScenario);
  const RunResult printed =
      Run("run " + Path("short.yaml") + " --print-config --set navigator.follower.target_speed_mps=1.25 --out " + Path("pc"));
  ASSERT_EQ(printed.exit_code, 0) << printed.err;
  EXPECT_EQ(printed.out.rfind("navigator:\n  timing:\n    map_rate_hz: 5\n", 0), 0u) << printed.out;
  EXPECT_NE(printed.out.find("    target_speed_mps: 1.25\n"), std::string::npos) << printed.out;
  EXPECT_FALSE(fs::exists(Path("pc"))) << "--print-config runs nothing";

  // The printed configuration is a preset; a run with it records the same values in result.json.
  WriteText("mine.yaml", printed.out);
  const RunResult run = Run("run " + Path("short.yaml") + " --preset " + Path("mine.yaml") + " -q --out " + Path("run"));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const nlohmann::json result = nlohmann::json::parse(ReadAll(Path("run/result.json")));
  EXPECT_EQ(result["config"]["navigator"]["follower"]["target_speed_mps"], 1.25);
  EXPECT_EQ(result["config"]["navigator"]["planner"]["vehicle"]["footprint_check"], "wheels");
  EXPECT_EQ(result["config"]["navigator"]["planner"]["vehicle"]["edge_tolerance_m"], "inf");
  // One row per map-and-plan cycle: 5 per simulated second.
  const std::string cycles = ReadAll(Path("run/cycles.csv"));
  EXPECT_EQ(cycles.rfind("time_s,cloud_points,map_ok,trigger,outcome,prepare_ms,map_ms,plan_ms,prepare_cpu_ms,map_cpu_ms,"
                         "plan_cpu_ms\n", 0), 0u) << cycles;
  EXPECT_NEAR(CountLines(cycles) - 1, 5.0 * result["sim_time_s"].get<double>(), 2.0);

  WriteText("broken.yaml", "navigator:\n  follower: {target_speed: 2}\n");
  const RunResult bad = Run("run " + Path("short.yaml") + " --preset " + Path("broken.yaml"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("broken.yaml:2: unknown key 'navigator.follower.target_speed'"), std::string::npos) << bad.err;
  EXPECT_EQ(Run("run " + Path("short.yaml") + " --preset " + Path("nothing.yaml")).exit_code, 2);
}

// The map backend is chosen by --map or navigator.map, recorded with its stage timings, and named
// per run by the suite.
TEST_F(CliTest, TheMapBackendIsChosenRecordedAndNamedPerRun) {
  WriteText("short.yaml", testing::kShortFlatScenario);
  const RunResult run = Run("run " + Path("short.yaml") + " --map elevation -q --out " + Path("elevation"));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const nlohmann::json result = nlohmann::json::parse(ReadAll(Path("elevation/result.json")));
  EXPECT_EQ(result["map"], "elevation");
  EXPECT_EQ(result["config"]["navigator"]["map"], "elevation");
  EXPECT_EQ(result["config"]["navigator"]["elevation"]["grid"]["resolution_m"], 0.1);
  for (const char* stage : {"fuse", "columns", "traversability"}) {
    EXPECT_GT(result["timing"]["map_stages"][stage]["calls"].get<int>(), 10) << stage;
  }
  EXPECT_GT(result["timing"]["map_update"]["p99_ms"].get<double>(), 0.0);

  const RunResult bad = Run("run " + Path("short.yaml") + " --set navigator.map=lidar");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(CountLines(bad.err), 1) << bad.err;
  EXPECT_NE(bad.err.find("'navigator.map' must be ovpc or octomap or elevation, got 'lidar'"), std::string::npos) << bad.err;

  const RunResult suite = Run("suite " + Path("short.yaml") + " -j 2 --sweep navigator.map=ovpc,octomap"
                              " --sweep navigator.octomap.resolution_m=0.3 --out " + Path("suite"));
  ASSERT_EQ(suite.exit_code, 0) << suite.out << suite.err;
  EXPECT_NE(suite.out.find(" octomap "), std::string::npos) << suite.out;
  const std::string junit = ReadAll(Path("suite/junit.xml"));
  EXPECT_NE(junit.find("name=\"seed=1 map=ovpc navigator.map=ovpc"), std::string::npos) << junit;
  EXPECT_NE(junit.find("name=\"seed=1 map=octomap navigator.map=octomap"), std::string::npos) << junit;
  const nlohmann::json summary = nlohmann::json::parse(ReadAll(Path("suite/summary.json")));
  ASSERT_EQ(summary["runs"].size(), 2u);
  EXPECT_EQ(summary["runs"][0]["map"], "ovpc");
  EXPECT_EQ(summary["runs"][1]["map"], "octomap");
  EXPECT_EQ(summary["runs"][1]["result"]["map"], "octomap");
  EXPECT_TRUE(summary["runs"][1]["result"]["timing"]["map_stages"].contains("insert"));
}

// A suite never loses its report: a malformed file is an error of its own and the others run; a run
// killed halfway is an error with no figures, not the figures of an earlier run in its folder.
TEST_F(CliTest, AFullDiskLosesADiagnosticFileWithAWarningAndTheResultWithAnError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full to stand for a full disk";
  WriteText("short.yaml", testing::kShortFlatScenario);
  // The plan log and the first mesh snapshot cannot be written: warnings; the result is whole.
  fs::create_directories(Path("diag"));
  fs::create_symlink("/dev/full", Path("diag/plans.csv"));
  // Maps take effect 0.1 s after they are started (navigator.timing.latency_s): at 1.1 s, then 2.1 s.
  fs::create_symlink("/dev/full", Path("diag/mesh_000_t1.1.ply"));
  const RunResult diag = Run("run " + Path("short.yaml") + " -q --set record.mesh_snapshot_period_s=1 --out " + Path("diag"));
  EXPECT_EQ(diag.exit_code, 0) << diag.err;
  EXPECT_NE(diag.err.find("warning: " + Path("diag/plans.csv")), std::string::npos) << diag.err;
  EXPECT_NE(diag.err.find("mesh_000_t1.1.ply"), std::string::npos) << diag.err;
  ASSERT_TRUE(fs::exists(Path("diag/result.json")));
  EXPECT_TRUE(nlohmann::json::parse(ReadAll(Path("diag/result.json")))["passed"].get<bool>());
  EXPECT_TRUE(fs::exists(Path("diag/mesh_001_t2.1.ply"))) << "the next snapshot is written";
  // The trajectory cannot be written: the run fails and leaves no result.json claiming anything.
  fs::create_directories(Path("traj"));
  fs::create_symlink("/dev/full", Path("traj/trajectory.csv"));
  const RunResult traj = Run("run " + Path("short.yaml") + " -q --out " + Path("traj"));
  EXPECT_EQ(traj.exit_code, 1);
  EXPECT_NE(traj.err.find("trajectory.csv: could not write it whole"), std::string::npos) << traj.err;
  EXPECT_FALSE(fs::exists(Path("traj/result.json")));
}

TEST_F(CliTest, SuiteReportsAMalformedFileAndAKilledRunAsErrorsAndTheRestInFull) {
  WriteText("short.yaml", testing::kShortFlatScenario);
  WriteText("broken.yaml", "name: broken\ntime_limit_s: soon\nroute: [[0, 0]]\n");
  // A run that takes far longer than the short one, killed while it runs; an earlier suite's
  // result.json sits in its folder.
  std::string slow = testing::kShortFlatScenario;
  slow.replace(slow.find("name: short_flat"), 16, "name: slow_flat");
  slow.replace(slow.find("time_limit_s: 8"), 15, "time_limit_s: 300");
  slow.replace(slow.find("[6, 0]]"), 7, "[15, 0], [15, 5], [0, 5], [0, 0]]");
  slow.replace(slow.find("goal: {x_m: 6.0"), 15, "goal: {x_m: 9.0");
  WriteText("slow.yaml", slow);
  fs::create_directories(Path("suite/slow_flat/seed_1"));
  WriteText("suite/slow_flat/seed_1/result.json", "{\"passed\": true, \"sim_time_s\": 1.0}\n");

  const std::string suite = std::string(OVPC_CLI_PATH) + " suite " + Path("short.yaml") + " " + Path("broken.yaml") + " " +
                            Path("slow.yaml") + " --jobs 2 --out " + Path("suite");
  // Kill the slow run's process once it has started (its parent, the suite, goes on). Only a child
  // that has exec'd `ovpc run ...slow.yaml` matches: a child forked but not yet exec'd still carries
  // the suite's command line, which names slow.yaml too (under load the short run was caught so).
  const std::string script = suite + " >" + Path("out.txt") + " 2>" + Path("err.txt") + " & s=$!; " +
                             "for i in $(seq 100); do p=$(pgrep -P $s -f \" run [^ ]*slow[.]yaml\") && break; sleep 0.1; done; sleep 1; "
                             "kill -9 $p; wait $s; echo $? >" + Path("code.txt");
  ASSERT_EQ(std::system(("bash -c '" + script + "'").c_str()), 0);
  EXPECT_EQ(std::stoi(ReadAll(Path("code.txt"))), 2) << "a malformed file is bad input";
  const std::string out = ReadAll(Path("out.txt"));
  EXPECT_NE(out.find("broken.yaml:2: 'time_limit_s' must be a number"), std::string::npos) << out;
  EXPECT_NE(out.find("killed by signal 9"), std::string::npos) << out;
  EXPECT_NE(out.find("1 of 3 runs passed"), std::string::npos) << out;
  const nlohmann::json summary = nlohmann::json::parse(ReadAll(Path("suite/summary.json")));
  EXPECT_EQ(summary["total"], 3);
  EXPECT_EQ(summary["passed"], 1);
  EXPECT_EQ(summary["errors"], 2);
  for (const auto& run : summary["runs"]) {
    if (run["scenario"] == "slow_flat") {
      EXPECT_FALSE(run["passed"].get<bool>());
      EXPECT_TRUE(run["result"].empty()) << "no figures of the earlier run: " << run["result"].dump();
    }
  }
  const std::string junit = ReadAll(Path("suite/junit.xml"));
  EXPECT_NE(junit.find("errors=\"2\""), std::string::npos) << junit;
  EXPECT_EQ(std::count(junit.begin(), junit.end(), '\n') > 5, true);
  EXPECT_NE(junit.find("<error message=\"killed by signal 9"), std::string::npos) << junit;
}

// Files that share a scenario name each get their own run folder and report their own figures.
TEST_F(CliTest, SuiteGivesFilesWithOneScenarioNameFoldersOfTheirOwn) {
  for (const char* dir : {"a", "b", "c"}) {
    fs::create_directories(Path(dir));
    WriteText(std::string(dir) + "/short.yaml", testing::kShortFlatScenario);
  }
  const RunResult r = Run("suite " + Path("a/short.yaml") + " " + Path("b/short.yaml") + " " + Path("c/short.yaml") +
                          " --jobs 2 --out " + Path("suite"));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* folder : {"short_flat", "short_flat_2", "short_flat_3"}) {
    EXPECT_TRUE(fs::exists(fs::path(Path("suite")) / folder / "seed_1" / "result.json")) << folder;
  }
}

// The runs with the longest time limits start first (so that a long run does not start last and
// leave the other jobs' cores idle); the reports keep the order of the inputs.
TEST_F(CliTest, SuiteStartsTheLongestRunsFirst) {
  WriteText("a.yaml", "name: a_short\ntime_limit_s: 2\nterrain: {kind: flat, size_m: [40, 20]}\nroute: [[0, 0], [6, 0]]\n");
  WriteText("b.yaml", "name: b_long\ntime_limit_s: 3\nterrain: {kind: flat, size_m: [40, 20]}\nroute: [[0, 0], [6, 0]]\n");
  const RunResult r = Run("suite " + Path("a.yaml") + " " + Path("b.yaml") + " --jobs 1 --out " + Path("suite"));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  // One job at a time: the runs end in the order they started.
  EXPECT_NE(r.err.find("[1/2] b_long seed 1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("[2/2] a_short seed 1"), std::string::npos) << r.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadAll(Path("suite/summary.json")));
  ASSERT_EQ(summary["runs"].size(), 2u);
  EXPECT_EQ(summary["runs"][0]["scenario"], "a_short");
  EXPECT_EQ(summary["runs"][1]["scenario"], "b_long");
}

// A scenario family: `ovpc run` refuses it, `ovpc family` writes its draws, `ovpc suite` draws, runs
// (one short draw) and judges it, and a malformed family is bad input with file and line.
TEST_F(CliTest, FamiliesAreDrawnRunAndJudged) {
  std::string family = testing::kShortFlatScenario;
  family.replace(family.find("name: short_flat"), 16, "name: short_family");
  family.replace(family.find("route: [[0, 0], [6, 0]]"), 23, "route: [[0, 0], [$goal_x, 0]]");
  family.replace(family.find("goal: {x_m: 6.0"), 15, "goal: {x_m: \"${goal_x}\"");
  family += "parameters:\n  goal_x: {grid: [6]}\n  post_y: {uniform: [4, 6]}\nobjects:\n  - cylinder: {x_m: 3, y_m: $post_y}\n"
            "expect:\n  - {when: \"goal_x < 10\", then: pass}\n  - {then: any, reason: far}\n";
  WriteText("family.yaml", family);

  const RunResult run = Run("run " + Path("family.yaml"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(CountLines(run.err), 1) << run.err;
  EXPECT_NE(run.err.find("this is a scenario family ('parameters:'): run its draws with `ovpc suite "), std::string::npos) << run.err;

  const RunResult drawn = Run("family " + Path("family.yaml") + " --samples 3 --seed 5 --out " + Path("drawn"));
  ASSERT_EQ(drawn.exit_code, 0) << drawn.err;
  EXPECT_NE(drawn.out.find("short_family: 3 draws (seed 5"), std::string::npos) << drawn.out;
  for (const char* draw : {"draw_000", "draw_001", "draw_002"}) {
    EXPECT_TRUE(fs::exists(fs::path(Path("drawn")) / "short_family" / draw / "scenario.yaml")) << draw;
  }
  EXPECT_EQ(CountLines(ReadAll(Path("drawn/short_family/draws.csv"))), 4);

  const RunResult suite = Run("suite " + Path("family.yaml") + " --samples 1 --seed 5 --out " + Path("su,ite"));
  ASSERT_EQ(suite.exit_code, 0) << suite.out << suite.err;
  const std::string draw_file = Path("su,ite/short_family/draw_000/scenario.yaml");
  EXPECT_EQ(ReadAll(draw_file), ReadAll(Path("drawn/short_family/draw_000/scenario.yaml"))) << "the same draw either way";
  EXPECT_NE(suite.out.find("pass: ok"), std::string::npos) << suite.out;
  EXPECT_NE(suite.out.find("short_family: pass rate against post_y (uniform, 5 bins)"), std::string::npos) << suite.out;
  const nlohmann::json result = nlohmann::json::parse(ReadAll(Path("su,ite/short_family/draw_000/seed_1/result.json")));
  EXPECT_EQ(result["extra"]["expectation"], "pass");
  EXPECT_EQ(result["extra"]["verdict"], "ok");
  EXPECT_EQ(result["extra"]["values"]["goal_x"], 6.0);
  EXPECT_EQ(result["extra"]["scenario_file"], draw_file);
  const nlohmann::json summary = nlohmann::json::parse(ReadAll(Path("su,ite/summary.json")));
  EXPECT_EQ(summary["runs"][0]["family"]["family"], "short_family");
  EXPECT_EQ(summary["families"][0]["draws"], 1);
  const std::string junit = ReadAll(Path("su,ite/junit.xml"));
  EXPECT_NE(junit.find("classname=\"short_family\" name=\"draw_000 seed=1 goal_x=6 post_y="), std::string::npos) << junit;
  EXPECT_NE(ReadAll(Path("su,ite/short_family/pass_rate.csv")).find("goal_x,6,6,6,1,1,0,0,0"), std::string::npos);
  EXPECT_TRUE(fs::exists(Path("su,ite/short_family/pass_rate_post_y.svg")));
  // A comma in a path is quoted in runs.csv: the columns stay in place.
  const std::string runs_csv = ReadAll(Path("su,ite/short_family/runs.csv"));
  EXPECT_NE(runs_csv.find(",\"" + draw_file + "\","), std::string::npos) << runs_csv;

  WriteText("bad.yaml", family.replace(family.find("{grid: [6]}"), 11, "{uniform: [6, 3]}"));
  const RunResult bad = Run("family " + Path("bad.yaml"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad.yaml:10: 'parameters.goal_x.uniform' must be [lo, hi] with lo < hi"), std::string::npos) << bad.err;
  const RunResult bad_suite = Run("suite " + Path("bad.yaml") + " --out " + Path("bad_suite"));
  EXPECT_EQ(bad_suite.exit_code, 2);
  EXPECT_NE(bad_suite.out.find("bad.yaml:10:"), std::string::npos) << bad_suite.out;
}

// A name is a name: a family called ".." or "." or an absolute path, or a scenario named like a
// path, is refused with exit 2, and nothing outside --out is made or removed.
TEST_F(CliTest, NamesThatArePathsAreRefusedAndNothingOutsideOutIsTouched) {
  fs::create_directories(Path("work/keep"));
  WriteText("work/keep/notes.txt", "mine\n");
  std::string family = testing::kShortFlatScenario;
  family += "parameters:\n  post_y: {uniform: [4, 6]}\nexpect:\n  - {then: any, reason: any}\n";
  for (const std::string& name : std::vector<std::string>{"..", ".", "/tmp/ovpc_abs_family_" + std::to_string(::getpid())}) {
    std::string text = family;
    text.replace(text.find("name: short_flat"), 16, "name: \"" + name + "\"");
    WriteText("family.yaml", text);
    for (const std::string& cmd : {std::string("family"), std::string("suite")}) {
      const RunResult r = Run(cmd + " " + Path("family.yaml") + " --samples 1 --out " + Path("work/out"));
      EXPECT_EQ(r.exit_code, 2) << cmd << " name " << name << ": " << r.out << r.err;
      EXPECT_EQ(ReadAll(Path("work/keep/notes.txt")), "mine\n") << cmd << " name " << name;
    }
  }
  EXPECT_FALSE(fs::exists("/tmp/ovpc_abs_family_" + std::to_string(::getpid())));
  std::string scenario = testing::kShortFlatScenario;
  scenario.replace(scenario.find("name: short_flat"), 16, "name: " + Path("work/keep"));
  WriteText("abs.yaml", scenario);
  const RunResult abs = Run("suite " + Path("abs.yaml") + " --out " + Path("work/out2"));
  EXPECT_EQ(abs.exit_code, 2) << abs.out << abs.err;
  EXPECT_EQ(fs::directory_iterator(Path("work/keep"))->path().filename(), "notes.txt");
  EXPECT_FALSE(fs::exists(Path("work/keep/seed_1")));
}

// A folder under --out that ovpc did not make is never cleared: the command refuses.
TEST_F(CliTest, AFolderNotMadeByOvpcIsNotCleared) {
  std::string family = testing::kShortFlatScenario;
  family.replace(family.find("name: short_flat"), 16, "name: fam");
  family += "parameters:\n  post_y: {uniform: [4, 6]}\nexpect:\n  - {then: any, reason: any}\n";
  WriteText("family.yaml", family);
  fs::create_directories(Path("out/fam"));
  WriteText("out/fam/thesis.tex", "years of work\n");
  const RunResult r = Run("family " + Path("family.yaml") + " --samples 1 --out " + Path("out"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(CountLines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("did not write"), std::string::npos) << r.err;
  EXPECT_EQ(ReadAll(Path("out/fam/thesis.tex")), "years of work\n");
  // A folder ovpc made is cleared and written again.
  fs::remove_all(Path("out/fam"));
  ASSERT_EQ(Run("family " + Path("family.yaml") + " --samples 1 --out " + Path("out")).exit_code, 0);
  ASSERT_EQ(Run("family " + Path("family.yaml") + " --samples 1 --out " + Path("out")).exit_code, 0);
  EXPECT_TRUE(fs::exists(Path("out/fam/draw_000/scenario.yaml")));
  // Two families with one name get folders of their own instead of overwriting each other's draws.
  WriteText("family2.yaml", family);
  const RunResult two = Run("family " + Path("family.yaml") + " " + Path("family2.yaml") + " --samples 1 --out " + Path("two"));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_TRUE(fs::exists(Path("two/fam/draw_000/scenario.yaml")));
  EXPECT_TRUE(fs::exists(Path("two/fam_2/draw_000/scenario.yaml")));
}

// Limits that cannot be met are refused at once with exit 2 and the count, before anything is
// planned or written.
TEST_F(CliTest, ImpossibleLimitsAreRefusedUpFront) {
  WriteText("short.yaml", testing::kShortFlatScenario);
  const std::string suite = "suite " + Path("short.yaml") + " --out " + Path("out") + " ";
  const RunResult seeds = Run(suite + "--seeds 1000000000");
  EXPECT_EQ(seeds.exit_code, 2);
  EXPECT_NE(seeds.err.find("--seeds must be 1-100000"), std::string::npos) << seeds.err;
  std::string sweep = "--sweep navigator.timing.latency_s=";
  for (int i = 0; i < 1000; ++i) sweep += (i ? "," : "") + std::to_string(0.1 + i * 1e-4);
  const RunResult combos = Run(suite + sweep + " " + sweep.substr(0, 8) + "navigator.follower.lookahead_gain_s=" + sweep.substr(28));
  EXPECT_EQ(combos.exit_code, 2);
  EXPECT_NE(combos.err.find("1000000 combinations"), std::string::npos) << combos.err;
  const RunResult overflow = Run(suite + "--first-seed 2147483647 --seeds 2");
  EXPECT_EQ(overflow.exit_code, 2);
  EXPECT_NE(overflow.err.find("largest seed"), std::string::npos) << overflow.err;
  const RunResult samples = Run(suite + "--samples -1");
  EXPECT_EQ(samples.exit_code, 2) << samples.err;
  EXPECT_EQ(Run("family " + Path("short.yaml") + " --samples -1 --out " + Path("out")).exit_code, 2);
  EXPECT_EQ(Run(suite + "--map ''").exit_code, 2);
  for (const char* empty : {"--preset ''", "--out ''"}) {
    const RunResult r = Run("suite " + Path("short.yaml") + " " + empty);
    EXPECT_EQ(r.exit_code, 2) << empty;
    EXPECT_NE(r.err.find("must name a file or folder"), std::string::npos) << r.err;
    EXPECT_EQ(Run("run " + Path("short.yaml") + " " + empty + (std::string(empty) == "--out ''" ? "" : " --out " + Path("run"))).exit_code, 2);
  }
  const RunResult twice_key = Run(suite + "--sweep navigator.timing.latency_s=0.1 --sweep navigator.timing.latency_s=0.2");
  EXPECT_EQ(twice_key.exit_code, 2);
  EXPECT_NE(twice_key.err.find("given twice"), std::string::npos) << twice_key.err;
  const RunResult run_map = Run("run " + Path("short.yaml") + " --map '' --out " + Path("run"));
  EXPECT_EQ(run_map.exit_code, 2);
  EXPECT_NE(run_map.err.find("--map must be"), std::string::npos) << run_map.err;
  EXPECT_FALSE(fs::exists(Path("out"))) << "nothing written";
  // An --out that cannot be made fails before the simulation, as bad input.
  WriteText("file.txt", "x");
  const RunResult unwritable = Run("run " + Path("short.yaml") + " --out " + Path("file.txt/sub"));
  EXPECT_EQ(unwritable.exit_code, 2);
  EXPECT_NE(unwritable.err.find("file.txt/sub"), std::string::npos) << unwritable.err;
  // The same file twice would share its run folders.
  const RunResult twice = Run("suite " + Path("short.yaml") + " " + dir_.string() + "/./short.yaml --out " + Path("out"));
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("given twice"), std::string::npos) << twice.err;
}

// One writer per folder: a second suite on a locked --out refuses with exit 2.
TEST_F(CliTest, ASecondWriterOfAFolderIsRefused) {
  WriteText("short.yaml", testing::kShortFlatScenario);
  fs::create_directories(Path("out"));
  const int fd = ::open(Path("out/.ovpc-lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const RunResult r = Run("suite " + Path("short.yaml") + " --out " + Path("out"));
  ::close(fd);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(CountLines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("another ovpc process is writing to this folder"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(Path("out/short_flat")));
}

// SIGTERM and SIGINT stop the suite's runs (none is left running) and the suite still writes the
// report of what finished, the rest as cancelled errors, and exits with 128 + the signal.
TEST_F(CliTest, ASignalStopsTheRunsAndTheSuiteStillReports) {
  // About 65 m of route with its goal at the end: no run ends by itself before the signal, even
  // at ten times real time (a goal on the route's first leg was reached in under a second).
  WriteText("slow.yaml",
            "name: slow_flat\ntime_limit_s: 300\nterrain: {kind: flat, size_m: [40, 20]}\n"
            "route: [[0, 0], [15, 0], [15, 5], [-15, 5], [-15, 0]]\n"
            "criteria:\n  goal: {x_m: -15.0, y_m: 0.0, radius_m: 1.0}\n  no_collision: true\n");
  for (const auto& [sig, name] : {std::pair<int, std::string>{SIGTERM, "SIGTERM"}, {SIGINT, "SIGINT"}}) {
    const std::string out = Path("suite_" + name);
    const std::string suite = std::string(OVPC_CLI_PATH) + " suite " + Path("slow.yaml") + " --seeds 3 --jobs 2 --out " + out;
    const std::string script = suite + " >" + Path("out.txt") + " 2>" + Path("err.txt") + " & s=$!; " +
                               "for i in $(seq 100); do pgrep -P $s >/dev/null && break; sleep 0.1; done; sleep 1; kill -" +
                               name.substr(3) + " $s; wait $s; echo $? >" + Path("code.txt") +
                               "; sleep 0.5; pgrep -f " + out + "/slow_fla[t] >" + Path("left.txt") + " || true";
    ASSERT_EQ(std::system(("bash -c '" + script + "'").c_str()), 0);
    EXPECT_EQ(std::stoi(ReadAll(Path("code.txt"))), 128 + sig) << ReadAll(Path("err.txt"));
    EXPECT_EQ(ReadAll(Path("left.txt")), "") << "runs left running after " << name;
    const nlohmann::json summary = nlohmann::json::parse(ReadAll(out + "/summary.json"));
    EXPECT_EQ(summary["total"], 3);
    EXPECT_EQ(summary["errors"], 3);
    EXPECT_NE(summary["runs"][0]["error"].get<std::string>().find("cancelled: the suite got " + name), std::string::npos)
        << summary.dump(2);
    EXPECT_NE(ReadAll(out + "/junit.xml").find("errors=\"3\""), std::string::npos);
  }
}

// Report files are whole or not there: on a full disk (a small tmpfs) or when a report's path is
// a folder, the suite exits 1 naming the file, and an earlier complete file is kept.
TEST_F(CliTest, AReportThatCannotBeWrittenIsAnErrorAndKeepsTheEarlierFile) {
  WriteText("broken.yaml", "name: broken\ntime_limit_s: soon\nroute: [[0, 0], [1, 0]]\n");
  fs::create_directories(Path("dir_out/summary.json"));
  const RunResult folder = Run("suite " + Path("broken.yaml") + " --out " + Path("dir_out"));
  EXPECT_EQ(folder.exit_code, 1) << folder.out << folder.err;
  EXPECT_NE(folder.err.find(Path("dir_out/summary.json")), std::string::npos) << folder.err;
  EXPECT_EQ(folder.out.find("wrote"), std::string::npos) << folder.out;

  if (::geteuid() != 0) GTEST_SKIP() << "mounting a small tmpfs needs root";
  const std::string mnt = Path("full");
  fs::create_directories(mnt);
  if (std::system(("mount -t tmpfs -o size=64k tmpfs " + mnt).c_str()) != 0) GTEST_SKIP() << "cannot mount a tmpfs";
  ASSERT_EQ(Run("suite " + Path("broken.yaml") + " --out " + mnt).exit_code, 2) << "fits while there is room";
  const std::string before = ReadAll(mnt + "/summary.json");
  ASSERT_FALSE(before.empty());
  std::system(("dd if=/dev/zero of=" + mnt + "/filler bs=1k count=1000 2>/dev/null").c_str());
  const RunResult full = Run("suite " + Path("broken.yaml") + " --out " + mnt);
  EXPECT_EQ(full.exit_code, 1) << full.out << full.err;
  EXPECT_NE(full.err.find("could not write it whole"), std::string::npos) << full.err;
  EXPECT_EQ(ReadAll(mnt + "/summary.json"), before) << "the complete file is kept";
  EXPECT_FALSE(fs::exists(mnt + "/junit.xml.part"));
  std::system(("umount " + mnt).c_str());
}

// Texts are escaped: a control character in an error stays out of junit.xml's bytes.
TEST_F(CliTest, ReportsEscapeWhatTheyQuote) {
  WriteText("ctrl.yaml", "name: ctrl\ntime_limit_s: 8\n\"bad\\x01key\": 1\nroute: [[0, 0], [1, 0]]\n");
  const RunResult r = Run("suite " + Path("ctrl.yaml") + " --out " + Path("out"));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  const std::string junit = ReadAll(Path("out/junit.xml"));
  EXPECT_EQ(junit.find('\x01'), std::string::npos) << junit;
  EXPECT_NE(junit.find("\\x01"), std::string::npos) << junit;
}

// junit.xml without the runs' wall-clock times (the only thing two runs of a run may differ in) and
// attachments (a merged report's are in the shards' folders).
std::string JunitWithoutTimes(const std::string& junit) {
  const std::string timeless = std::regex_replace(junit, std::regex(" time=\"[^\"]*\""), "");
  return std::regex_replace(timeless, std::regex("<system-out>[^<]*</system-out>"), "");
}

// A suite split into shards (--shard K/N) and merged (`ovpc merge`) reports what the unsharded
// suite reports: the same testcases in the same order, the same verdicts. Each run is in one shard.
TEST_F(CliTest, ShardsMergeIntoTheUnshardedReport) {
  WriteText("short.yaml", testing::kShortFlatScenario);
  const RunResult whole = Run("suite " + Path("short.yaml") + " --seeds 3 --jobs 2 --out " + Path("whole"));
  ASSERT_EQ(whole.exit_code, 0) << whole.out << whole.err;
  const std::string shards = std::string(OVPC_CLI_PATH) + " suite " + Path("short.yaml") + " --seeds 3 --jobs 1 --shard ";
  ASSERT_EQ(std::system((shards + "1/3 --out " + Path("s1") + " >/dev/null 2>&1 & " + shards + "2/3 --out " + Path("s2") +
                         " >/dev/null 2>&1 & " + shards + "3/3 --out " + Path("s3") + " >/dev/null 2>&1; wait")
                            .c_str()),
            0);
  for (const char* shard : {"s1", "s2", "s3"}) {
    const nlohmann::json s = nlohmann::json::parse(ReadAll(Path(std::string(shard) + "/summary.json")));
    EXPECT_EQ(s["runs"].size(), 1u) << shard << ": three equal runs, one in each shard";
    EXPECT_EQ(s["suite"]["plan"]["runs"], 3);
  }
  const RunResult merged = Run("merge " + Path("s3") + " " + Path("s1") + " " + Path("s2") + " --out " + Path("merged"));
  ASSERT_EQ(merged.exit_code, 0) << merged.out << merged.err;
  EXPECT_NE(merged.out.find("3 of 3 runs passed"), std::string::npos) << merged.out;
  const std::string merged_junit = ReadAll(Path("merged/junit.xml"));
  EXPECT_EQ(JunitWithoutTimes(merged_junit), JunitWithoutTimes(ReadAll(Path("whole/junit.xml"))));
  // The merged junit.xml's attachments are the shards' files, relative to its folder.
  const std::regex attachment("\\[\\[ATTACHMENT\\|([^\\]]*)\\]\\]");
  int attachments = 0;
  for (auto it = std::sregex_iterator(merged_junit.begin(), merged_junit.end(), attachment); it != std::sregex_iterator(); ++it) {
    ++attachments;
    EXPECT_TRUE(fs::exists(fs::path(Path("merged")) / (*it)[1].str())) << (*it)[1].str();
  }
  EXPECT_EQ(attachments, 3) << "topdown.png of each run" << merged_junit;
  const nlohmann::json a = nlohmann::json::parse(ReadAll(Path("whole/summary.json")));
  const nlohmann::json b = nlohmann::json::parse(ReadAll(Path("merged/summary.json")));
  ASSERT_EQ(b["runs"].size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    for (const char* key : {"index", "scenario", "seed", "settings", "map", "passed", "exit_code"}) {
      EXPECT_EQ(b["runs"][i][key], a["runs"][i][key]) << "run " << i << " " << key;
    }
    EXPECT_EQ(b["runs"][i]["result"]["passed"], a["runs"][i]["result"]["passed"]) << i;
  }
  EXPECT_EQ(b["passed"], a["passed"]);
  EXPECT_EQ(b["suite"]["plan"], a["suite"]["plan"]) << "the same planned runs, sharded or not";
  EXPECT_EQ(b["suite"]["merged_shards"], 3);
  // The merged report.html is written from the shards' results; its run pages link to the run
  // folders in the shards' folders.
  const std::string report = ReadAll(Path("merged/report.html"));
  EXPECT_NE(report.find("3 of 3 runs passed"), std::string::npos);
  EXPECT_NE(report.find("<dt>shards</dt><dd>merged from 3</dd>"), std::string::npos) << report;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string page = ReadAll(Path("merged/runs/" + std::to_string(i) + ".html"));
    const std::smatch m = [&] {
      std::smatch found;
      std::regex_search(page, found, std::regex("href=\"([^\"]*)/result\\.json\""));
      return found;
    }();
    ASSERT_EQ(m.size(), 2u) << page;
    const fs::path folder = fs::path(Path("merged/runs")) / m[1].str();
    EXPECT_TRUE(fs::exists(folder / "result.json")) << folder;
    EXPECT_EQ(fs::canonical(folder), fs::canonical(b["runs"][i]["out"].get<std::string>()));
  }
  EXPECT_NE(ReadAll(Path("merged/summary.md")).find("# ovpc suite: 3 of 3 runs passed"), std::string::npos);
}

// A merge is of every shard of one suite, once each, or nothing is written: a missing, repeated,
// foreign or stopped shard is refused (exit 2, one line naming the folder). The shards here hold
// only malformed files' errors, so that nothing is simulated.
TEST_F(CliTest, AMergeOfMissingRepeatedOrForeignShardsIsRefused) {
  WriteText("a.yaml", "name: a\ntime_limit_s: [\n");
  WriteText("b.yaml", "name: b\nroute: 3\n");
  const std::string suite = "suite " + Path("a.yaml") + " " + Path("b.yaml") + " --shard ";
  for (const char* k : {"1", "2"}) ASSERT_EQ(Run(suite + k + "/2 --out " + Path(std::string("s") + k)).exit_code, 2);
  ASSERT_EQ(Run("suite " + Path("a.yaml") + " --shard 2/2 --out " + Path("other_inputs")).exit_code, 2);
  ASSERT_EQ(Run(suite + "2/2 --seeds 2 --out " + Path("other_seeds")).exit_code, 2);
  ASSERT_EQ(Run(suite + "2/3 --out " + Path("other_count")).exit_code, 2);
  WriteText("b.yaml", "name: b\nroute: 4\n");  // the same names, another file: another planned run list
  ASSERT_EQ(Run(suite + "2/2 --out " + Path("other_plan")).exit_code, 2);
  fs::create_directories(Path("empty"));
  fs::copy(Path("s2"), Path("stopped"), fs::copy_options::recursive);
  nlohmann::json stopped = nlohmann::json::parse(ReadAll(Path("stopped/summary.json")));
  stopped["suite"]["stop_signal"] = 15;
  WriteText("stopped/summary.json", stopped.dump());
  fs::copy(Path("s2"), Path("other_build"), fs::copy_options::recursive);
  nlohmann::json build = stopped;
  build["suite"]["stop_signal"] = 0;
  build["suite"]["build"] = "v0-elsewhere";
  WriteText("other_build/summary.json", build.dump());
  const std::pair<std::string, std::string> refused[] = {
      {Path("s1"), "shard 2/2 is missing"},
      {Path("s1") + " " + Path("s1") + " " + Path("s2"), Path("s1") + ": shard 1/2 again (also " + Path("s1") + ")"},
      {Path("s1") + " " + Path("other_inputs"), Path("other_inputs") + ": a shard of another suite than " + Path("s1") + ": other inputs"},
      {Path("s1") + " " + Path("other_seeds"), Path("other_seeds") + ": a shard of another suite than " + Path("s1") + ": other seeds"},
      {Path("s1") + " " + Path("other_count"), "another shard count (3, not 2)"},
      {Path("s1") + " " + Path("other_plan"), Path("other_plan") + ": a shard of another suite than " + Path("s1") + ": another planned run list"},
      {Path("s1") + " " + Path("other_build"), Path("other_build") + ": a shard of another suite than " + Path("s1") + ": another build (v0-elsewhere"},
      {Path("s1") + " " + Path("stopped"), Path("stopped") + ": shard 2/2 was stopped by signal 15"},
      {Path("s1") + " " + Path("empty"), Path("empty") + ": no summary.json"},
  };
  for (const auto& [folders, message] : refused) {
    const RunResult r = Run("merge " + folders + " --out " + Path("merged"));
    EXPECT_EQ(r.exit_code, 2) << folders;
    EXPECT_EQ(CountLines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(Path("merged"))) << "nothing written: " << folders;
  }
  const RunResult ok = Run("merge " + Path("s2") + " " + Path("s1") + " --out " + Path("merged"));
  EXPECT_EQ(ok.exit_code, 2) << "the whole suite's exit code: a malformed file among its inputs";
  const nlohmann::json summary = nlohmann::json::parse(ReadAll(Path("merged/summary.json")));
  ASSERT_EQ(summary["runs"].size(), 2u);
  EXPECT_EQ(summary["runs"][0]["scenario"], "a") << "in the planned order";
  EXPECT_EQ(summary["runs"][1]["scenario"], "b");
  EXPECT_EQ(Run("merge --out " + Path("x")).exit_code, 2);
  EXPECT_NE(Run("merge --help").out.find("--out"), std::string::npos);
}

// `ovpc compare OLD NEW`: the runs that changed verdict (a regression first), pass rates and time to
// goal per scenario; exit 1 on a regression, 0 otherwise, 2 for a missing or invalid summary.json.
TEST_F(CliTest, CompareNamesTheRegressedRunsAndExitsOne) {
  WriteText("short.yaml", testing::kShortFlatScenario);
  // An earlier suite's page of a run this suite does not have goes; a page of someone else's stays.
  fs::create_directories(Path("old/runs"));
  WriteText("old/runs/7.html", "earlier");
  WriteText("old/runs/notes.html", "mine");
  ASSERT_EQ(Run("suite " + Path("short.yaml") + " --seeds 2 --jobs 2 --out " + Path("old")).exit_code, 0);
  EXPECT_FALSE(fs::exists(Path("old/runs/7.html")));
  EXPECT_TRUE(fs::exists(Path("old/runs/notes.html")));
  EXPECT_TRUE(fs::exists(Path("old/runs/0.html")) && fs::exists(Path("old/runs/1.html")));
  // The later suite: seed 2 fails, seed 1 takes a second longer.
  fs::create_directories(Path("new"));
  nlohmann::json later = nlohmann::json::parse(ReadAll(Path("old/summary.json")));
  ASSERT_EQ(later["runs"].size(), 2u);
  later["runs"][0]["result"]["sim_time_s"] = later["runs"][0]["result"]["sim_time_s"].get<double>() + 1.0;
  later["runs"][1]["exit_code"] = 1;
  later["runs"][1]["passed"] = false;
  later["runs"][1]["result"]["passed"] = false;
  WriteText("new/summary.json", later.dump());

  const RunResult r = Run("compare " + Path("old") + " " + Path("new") + " --out " + Path("cmp"));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("**1 runs regressed (passed, now do not), 0 fixed**; 2 runs in both"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| short_flat seed=2 map=ovpc | regressed | pass | FAIL |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| short_flat | ovpc |  | 2/2 (100 %) | 1/2 (50 %) | -50.0 pp | "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("+1.0 s"), std::string::npos) << "seed 1 reached the goal in both, a second later" << r.out;
  EXPECT_EQ(ReadAll(Path("cmp/compare.md")) + "\nwrote " + Path("cmp/compare.md") + "\n", r.out);

  const RunResult back = Run("compare " + Path("new/summary.json") + " " + Path("old"));
  EXPECT_EQ(back.exit_code, 0) << back.out << back.err;
  EXPECT_NE(back.out.find("**0 runs regressed (passed, now do not), 1 fixed**"), std::string::npos) << back.out;
  EXPECT_TRUE(fs::exists(Path("old/compare.md"))) << "without --out, beside NEW";

  WriteText("bad.json", "{");
  const std::pair<std::string, std::string> refused[] = {
      {Path("old") + " " + Path("none"), Path("none") + ": no such file"},
      {Path("cmp") + " " + Path("old"), Path("cmp/summary.json") + ": no such file"},
      {Path("bad.json") + " " + Path("old"), Path("bad.json") + ": not a suite's result file"},
  };
  for (const auto& [args, message] : refused) {
    const RunResult bad = Run("compare " + args);
    EXPECT_EQ(bad.exit_code, 2) << args;
    EXPECT_EQ(CountLines(bad.err), 1) << bad.err;
    EXPECT_NE(bad.err.find(message), std::string::npos) << bad.err;
  }
  EXPECT_EQ(Run("compare " + Path("old")).exit_code, 2);
  EXPECT_NE(Run("compare --help").out.find("regressed"), std::string::npos);
}

}  // namespace
}  // namespace ovpc
