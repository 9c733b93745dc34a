#include "ovpc/scenarios/scenario_yaml.h"

#include "ovpc/scenarios/family.h"

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ovpc::scenarios {
namespace {

const char* kMinimal = R"(name: tiny
time_limit_s: 5
terrain: {kind: flat, size_m: [30, 20]}
objects:
  - carport: {x_m: 6.0, y_m: 0.0, roof_height_m: 2.5}
  - sphere: {x_m: 3.0, y_m: 4.0, radius_m: 0.5}
route: [[0, 0], [10, 0]]
navigator:
  ovpc: {mapper: {ghpr: {gamma: -0.02}, traversability: {alpha_max_rad: 0.4363323129985824}}}
  buffer: {max_scans: 20}
criteria:
  goal: {x_m: 10, y_m: 0, radius_m: 1.0}
  max_pitch_deg: 12
  forbidden:
    - {name: pit, min_m: [4, -1], max_m: [5, 1]}
)";

std::string ErrorOf(const std::string& yaml, const std::vector<std::string>& settings = {}) {
  try {
    ParseScenario(yaml, "test.yaml", settings);
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

TEST(ScenarioYamlTest, ReadsEverySection) {
  const Scenario s = ParseScenario(kMinimal, "test.yaml");
  EXPECT_EQ(s.name, "tiny");
  EXPECT_DOUBLE_EQ(s.time_limit_s, 5.0);
  EXPECT_DOUBLE_EQ(s.sim.world.terrain.size_x_m, 30.0);
  ASSERT_EQ(s.sim.world.carports.size(), 1u);
  ASSERT_EQ(s.sim.world.ellipsoids.size(), 1u);
  EXPECT_DOUBLE_EQ(s.sim.world.ellipsoids[0].radius_z_m, 0.5);
  ASSERT_EQ(s.route_m.size(), 2u);
  EXPECT_DOUBLE_EQ(s.navigator.ovpc.mapper.ghpr.gamma, -0.02);
  EXPECT_NEAR(RadToDeg(s.navigator.ovpc.mapper.traversability.alpha_max_rad), 25.0, 1e-12);
  EXPECT_EQ(s.navigator.buffer.max_scans, 20);
  ASSERT_TRUE(s.criteria.goal_m.has_value());
  EXPECT_DOUBLE_EQ(s.criteria.goal_m->x(), 10.0);
  ASSERT_TRUE(s.criteria.max_pitch_deg.has_value());
  ASSERT_EQ(s.criteria.forbidden.size(), 1u);
  EXPECT_EQ(s.criteria.forbidden[0].name, "pit");
}

TEST(ScenarioYamlTest, SettingsOverrideValues) {
  const Scenario s = ParseScenario(kMinimal, "test.yaml", {"navigator.ovpc.mapper.ghpr.gamma=-0.01", "time_limit_s=9"});
  EXPECT_DOUBLE_EQ(s.navigator.ovpc.mapper.ghpr.gamma, -0.01);
  EXPECT_DOUBLE_EQ(s.time_limit_s, 9.0);
}

TEST(ScenarioYamlTest, UnknownKeysAndWrongTypesNameFileLineAndKey) {
  std::string bad = kMinimal;
  bad.replace(bad.find("max_scans"), 9, "max_scanz");
  EXPECT_EQ(ErrorOf(bad).rfind("test.yaml:10: unknown key 'navigator.buffer.max_scanz'", 0), 0u) << ErrorOf(bad);

  bad = kMinimal;
  bad.replace(bad.find("time_limit_s: 5") + 14, 1, "soon");
  EXPECT_NE(ErrorOf(bad).find("test.yaml:2: 'time_limit_s' must be a number, got 'soon'"), std::string::npos)
      << ErrorOf(bad);

  bad = kMinimal;
  bad.replace(bad.find("sphere"), 6, "cone");
  EXPECT_NE(ErrorOf(bad).find("unknown object type 'cone'"), std::string::npos) << ErrorOf(bad);

  bad = kMinimal;
  bad.replace(bad.find("[10, 0]"), 7, "[10]");
  EXPECT_NE(ErrorOf(bad).find("'route[1]' must be [x, y]"), std::string::npos) << ErrorOf(bad);

  EXPECT_NE(ErrorOf("name: x\ntime_limit_s: 3\n").find("'route' is required"), std::string::npos);
  EXPECT_NE(ErrorOf("name: [unclosed\n").find("not valid YAML"), std::string::npos);
  EXPECT_NE(ErrorOf(kMinimal, {"navigator.ovpc.mapper.ghpr.gamma=0.5"}).find("gamma"), std::string::npos);
  EXPECT_NE(ErrorOf(kMinimal, {"nonsense"}).find("key=value"), std::string::npos);
  EXPECT_NE(ErrorOf(kMinimal, {"navigator.preparation.footprint_prior_blend_m=-0.5"}).find("footprint_prior_blend_m"),
            std::string::npos);
  EXPECT_DOUBLE_EQ(ParseScenario(kMinimal, "test.yaml", {"navigator.preparation.footprint_prior_blend_m=0.75"})
                       .navigator.preparation.footprint_prior_blend_m,
                   0.75);
  EXPECT_NE(ErrorOf(kMinimal, {"navigator.ovpc.mapper.ghpr.gammma=-0.1"}).find("unknown key 'navigator.ovpc.mapper.ghpr.gammma'"),
            std::string::npos);
}

TEST(ScenarioYamlTest, ErrorsAreOneLineWhateverCharactersTheFileHolds) {
  // A key with an escaped newline, and a backslash before a line break (yaml-cpp's message then ends
  // in the raw newline): both gave messages of two lines.
  std::string bad = kMinimal;
  bad.replace(bad.find("max_scans"), 9, "\"max\\nscans\"");
  const std::string key = ErrorOf(bad);
  EXPECT_EQ(key.find('\n'), std::string::npos) << key;
  EXPECT_NE(key.find("unknown key 'navigator.buffer.max\\x0ascans'"), std::string::npos) << key;
  for (const std::string& text : {std::string("name: \"a\\\nb\"\n"), std::string("name: x\n  bumps:\x08\x00\n")}) {
    const std::string error = ErrorOf(text);
    EXPECT_NE(error, "") << "accepted";
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    for (const char c : error) EXPECT_GE(static_cast<unsigned char>(c), 0x20u) << error;
  }
}

TEST(ScenarioYamlTest, MissingFileIsAnError) {
  EXPECT_THROW(LoadScenario("/nonexistent/scenario.yaml"), ScenarioError);
}

TEST(ScenarioYamlTest, EveryBundledScenarioLoads) {
  // Every *.yaml beside the runner (the suite; the families are in families/ and load as families).
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(OVPC_SOURCE_DIR) + "/scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(LoadScenario(entry.path().string()));
    ++loaded;
  }
  EXPECT_GE(loaded, 10);  // carport_2p5 ... underpass_2p5 and mixed_long
}

}  // namespace
}  // namespace ovpc::scenarios

namespace ovpc::scenarios {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The preset file without its comments and blank lines: what --print-config prints for it.
std::string WithoutComments(const std::string& yaml) {
  std::istringstream in(yaml);
  std::string line, out;
  while (std::getline(in, line)) {
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    if (!line.empty()) out += line + "\n";
  }
  return out;
}

TEST(RunConfigTest, TheDefaultPresetListsEverySettingAndPrintsAsItReads) {
  const std::string file = std::string(OVPC_SOURCE_DIR) + "/navigation/presets/default.yaml";
  EXPECT_EQ(DefaultPreset().yaml, ReadText(file)) << "the built-in preset is the file";
  const Scenario s = ParseScenario(kMinimal, "test.yaml", {"navigator.ovpc.mapper.ghpr.gamma=-0.03",
                                                           "navigator.ovpc.mapper.traversability.alpha_max_rad=0.5235987755982988",
                                                           "navigator.buffer.max_scans=25"});
  // Every key the Configs declare is in the file, in the same order, with the value it reads as;
  // the testbed's record: settings are not the robot's, and follow with their own defaults.
  EXPECT_EQ(FormatRunConfig(s),
            WithoutComments(ReadText(file)) + "record:\n  record_rate_hz: 10\n  mesh_snapshot_period_s: 10\n  mcap: false\n"
                                                  "  mcap_scan_period_s: 0.5\n  mcap_map_period_s: 1\n");
}

TEST(RunConfigTest, PrintedConfigReadsBackAsAPresetToTheSameConfig) {
  const Scenario a = LoadScenario(std::string(OVPC_SOURCE_DIR) + "/scenarios/slope_35_detour.yaml");
  const std::string printed = FormatRunConfig(a);
  EXPECT_NE(printed.find("placement: wheel_contacts"), std::string::npos) << "the scenario's own keys are in it";
  const Scenario b = ParseScenario("name: plain\ntime_limit_s: 5\nroute: [[0, 0], [5, 0]]\n", "plain.yaml", {},
                                   Preset{printed, "printed.yaml"});
  EXPECT_EQ(FormatRunConfig(b), printed);
  EXPECT_EQ(b.navigator.planner.vehicle.placement, planner::VehicleBox::Placement::kWheelContacts);
  EXPECT_EQ(b.navigator.local_goal.mode, planner::LocalGoalSelection::Config::Mode::kReachable);
}

TEST(RunConfigTest, BadPresetsAndTheOldParamsSectionAreErrorsNamingFileAndLine) {
  const auto error = [](const std::string& scenario, const Preset& preset, const std::vector<std::string>& set = {}) {
    try {
      ParseScenario(scenario, "test.yaml", set, preset);
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error(kMinimal, Preset{"navigator:\n  buffer:\n    max_scanz: 3\n", "p.yaml"})
                .rfind("p.yaml:3: unknown key 'navigator.buffer.max_scanz'", 0),
            0u);
  EXPECT_EQ(error(kMinimal, Preset{"navigator:\n  planner:\n    vehicle: {placement: floating}\n", "p.yaml"})
                .rfind("p.yaml:3: 'navigator.planner.vehicle.placement' must be nearest_point or wheel_contacts", 0),
            0u);
  EXPECT_EQ(error(kMinimal, Preset{"navigator:\n  timing:\n    map_rate_hz: 0\n", "p.yaml"})
                .rfind("p.yaml:3: in 'navigator.timing': navigator.timing.map_rate_hz must be in (0, 100]", 0),
            0u)
      << error(kMinimal, Preset{"navigator:\n  timing:\n    map_rate_hz: 0\n", "p.yaml"});
  // A key that moved into a section is refused with its new place.
  EXPECT_EQ(error(kMinimal, Preset{"navigator:\n  buffer: {}\n  latency_s: 0.1\n", "p.yaml"})
                .rfind("p.yaml:3: 'navigator.latency_s' is now 'navigator.timing.latency_s'", 0),
            0u)
      << error(kMinimal, Preset{"navigator:\n  buffer: {}\n  latency_s: 0.1\n", "p.yaml"});
  EXPECT_NE(error(kMinimal, DefaultPreset(), {"navigator.progress_back_m=3"})
                .find("'navigator.progress_back_m' is now 'navigator.progress.back_m'"),
            std::string::npos);
  // A section's own rule is reported at the section, a rule across sections at 'navigator'.
  EXPECT_EQ(error(kMinimal, Preset{"navigator:\n  follower:\n    lookahead_min_m: -1\n", "p.yaml"})
                .rfind("p.yaml:3: in 'navigator.follower': ", 0),
            0u)
      << error(kMinimal, Preset{"navigator:\n  follower:\n    lookahead_min_m: -1\n", "p.yaml"});
  std::string tiny = kMinimal;
  tiny.replace(tiny.find("  buffer:"), 0, "  vehicle: {height_m: 0.05}\n");
  EXPECT_NE(error(tiny, DefaultPreset()).find("test.yaml:9: in 'navigator': "), std::string::npos)
      << error(tiny, DefaultPreset());
  EXPECT_NE(error(kMinimal, Preset{"navigator:\n  vehicle: {length_m: 1e9}\n", "p.yaml"}).find("length_m must be in (0, 20] m"),
            std::string::npos);
  std::string old = kMinimal;
  old.insert(old.find("criteria:"), "params:\n  loop: {goal_candidates: 2}\n");
  EXPECT_EQ(error(old, DefaultPreset()).rfind("test.yaml:12: 'params' is gone", 0), 0u) << error(old, DefaultPreset());
  EXPECT_THROW(LoadPreset("/nonexistent/preset.yaml"), ScenarioError);
}

}  // namespace
}  // namespace ovpc::scenarios

namespace ovpc::scenarios {
namespace {

std::string LoadError(const std::string& yaml) {
  try {
    ParseScenario(yaml, "bad.yaml");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

TEST(ScenarioValidationTest, ValuesThatWouldRunForeverOrOffTheWorldAreRefused) {
  const std::string base = "name: b\ntime_limit_s: 5\nterrain: {kind: flat, size_m: [40, 20]}\n";
  EXPECT_NE(LoadError(base + "route: [[0, 0], [.nan, 0]]\n").find("bad.yaml:4: 'route[1]' must be a number, got '.nan'"),
            std::string::npos)
      << LoadError(base + "route: [[0, 0], [.nan, 0]]\n");
  EXPECT_NE(LoadError(base + "route: [[0, 0], [25, 0]]\n").find("route[1] lies off the terrain"), std::string::npos);
  EXPECT_NE(LoadError(base + "route: [[0, 0], [5, 0]]\nstart: {x_m: -30}\n").find("start lies off the terrain"),
            std::string::npos);
  EXPECT_NE(LoadError(base + "route: [[0, 0], [5, 0]]\ncriteria: {goal: {x_m: 5, y_m: 50}}\n").find("criteria.goal"),
            std::string::npos);
  const std::string forever = "name: b\ntime_limit_s: .inf\nterrain: {kind: flat, size_m: [40, 20]}\nroute: [[0, 0], [5, 0]]\n";
  EXPECT_NE(LoadError(forever).find("time_limit_s must be in (0, 86400] s"), std::string::npos) << LoadError(forever);
  const std::string huge = "name: b\ntime_limit_s: 5\nterrain: {kind: flat, size_m: [1000, 1000]}\nroute: [[0, 0], [5, 0]]\n";
  EXPECT_NE(LoadError(huge).find("more than 4 million vertices"), std::string::npos) << LoadError(huge);
  // A size over a cell beyond int (5e12 cells) is bounded before it is converted.
  const std::string vast = "name: b\ntime_limit_s: 5\nterrain: {kind: flat, size_m: [1e12, 10]}\nroute: [[0, 0], [5, 0]]\n";
  EXPECT_NE(LoadError(vast).find("more than 4 million vertices"), std::string::npos) << LoadError(vast);
  const std::string twice = "name: b\ntime_limit_s: 5\ntime_limit_s: 9\nroute: [[0, 0], [5, 0]]\n";
  EXPECT_EQ(LoadError(twice).rfind("bad.yaml:3: duplicate key 'time_limit_s'", 0), 0u) << LoadError(twice);
  const std::string twice_inside = base + "route: [[0, 0], [5, 0]]\nnavigator: {buffer: {max_scans: 3, max_scans: 4}}\n";
  EXPECT_NE(LoadError(twice_inside).find("duplicate key 'navigator.buffer.max_scans'"), std::string::npos)
      << LoadError(twice_inside);
  const std::string odd_key = base + "route: [[0, 0], [5, 0]]\n? [a, b]\n: 1\n";
  EXPECT_EQ(LoadError(odd_key).rfind("bad.yaml:", 0), 0u) << LoadError(odd_key);
}

}  // namespace
}  // namespace ovpc::scenarios

namespace ovpc::scenarios {
namespace {

TEST(ScenarioYamlTest, APostFieldIsPostsOnAJitteredGridTheSameEveryTime) {
  const std::string yaml =
      "name: field\ntime_limit_s: 5\nterrain: {kind: flat, size_m: [60, 40]}\nroute: [[0, 0], [5, 0]]\n"
      "objects:\n  - post_field: {x_m: [6, 30], y_m: [-9, 9], spacing_m: 3, jitter: JITTER, radius_m: 0.1, seed: SEED}\n";
  const auto load = [&](const char* jitter, const char* seed) {
    std::string s = yaml;
    s.replace(s.find("JITTER"), 6, jitter);
    s.replace(s.find("SEED"), 4, seed);
    return ParseScenario(s, "field.yaml").sim.world.cylinders;
  };
  const auto rows = load("0", "1");
  ASSERT_EQ(rows.size(), 9u * 7u);  // x 6, 9, ..., 30; y -9, -6, ..., 9
  EXPECT_DOUBLE_EQ(rows.front().x_m, 6.0);
  EXPECT_DOUBLE_EQ(rows.back().y_m, 9.0);
  const auto a = load("0.8", "1"), b = load("0.8", "1"), c = load("0.8", "2");
  ASSERT_EQ(a.size(), rows.size());
  bool same = true, differs = false;
  double closest = 1e9;
  for (std::size_t i = 0; i < a.size(); ++i) {
    same = same && a[i].x_m == b[i].x_m && a[i].y_m == b[i].y_m;
    differs = differs || a[i].x_m != c[i].x_m;
    EXPECT_LE(std::abs(a[i].x_m - rows[i].x_m), 0.4 * 3.0 + 1e-12);
    for (std::size_t j = 0; j < i; ++j) closest = std::min(closest, std::hypot(a[i].x_m - a[j].x_m, a[i].y_m - a[j].y_m));
  }
  EXPECT_TRUE(same);
  EXPECT_TRUE(differs);
  EXPECT_GE(closest, 3.0 * (1.0 - 0.8) - 1e-9);
  // Posts that would overlap, a jitter out of range and a field of millions of posts are refused.
  for (const auto& [jitter, spacing] : std::vector<std::pair<std::string, std::string>>{
           {"0.95", "3"}, {"1.5", "3"}, {"0", "0.1"}}) {
    std::string s = yaml;
    s.replace(s.find("JITTER"), 6, jitter);
    s.replace(s.find("SEED"), 4, "1");
    s.replace(s.find("spacing_m: 3"), 12, "spacing_m: " + spacing);
    if (spacing == "0.1") s.replace(s.find("radius_m: 0.1"), 13, "radius_m: 0.01");
    try {
      ParseScenario(s, "field.yaml");
      ADD_FAILURE() << jitter << " " << spacing;
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("field.yaml:6"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace ovpc::scenarios

namespace ovpc::scenarios {
namespace {

namespace fs = std::filesystem;

// A scratch folder for files that are not scenario files, removed after the test.
class NotAFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ovpc_not_a_file_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string PathOf(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// The message of every loader on `path`, each of which must refuse it quickly.
std::vector<std::string> LoaderErrors(const std::string& path) {
  std::vector<std::string> errors;
  const auto error_of = [&errors](const auto& load) {
    const auto start = std::chrono::steady_clock::now();
    try {
      load();
      errors.push_back("accepted");
    } catch (const ScenarioError& e) {
      errors.push_back(e.what());
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1)) << errors.back();
  };
  error_of([&] { LoadScenario(path); });
  error_of([&] { LoadPreset(path); });
  error_of([&] { LoadFamily(path); });
  EXPECT_FALSE(IsFamilyFile(path));
  return errors;
}

// Each loader refuses what is not a regular file before opening it (a FIFO would block the open,
// /dev/zero would be read for ever), and a file over the limit before reading it.
TEST_F(NotAFileTest, LoadersRefuseWhatIsNotAFileOrTooLarge) {
  for (const std::string& e : LoaderErrors(dir_.string())) {
    EXPECT_EQ(e.rfind(dir_.string() + ": is a directory, not a ", 0), 0u) << e;
  }
  const std::string fifo = PathOf("fifo.yaml");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& e : LoaderErrors(fifo)) EXPECT_EQ(e, fifo + ": is not a regular file (a FIFO)");
  if (fs::exists("/dev/zero")) {
    for (const std::string& e : LoaderErrors("/dev/zero")) EXPECT_EQ(e, "/dev/zero: is not a regular file (a character device)");
  }
  const std::string socket_path = PathOf("socket.yaml");
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof address.sun_path, "%s", socket_path.c_str());
  if (fd >= 0 && ::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0) {
    for (const std::string& e : LoaderErrors(socket_path)) EXPECT_EQ(e, socket_path + ": is not a regular file (a socket)");
  }
  if (fd >= 0) ::close(fd);
  const std::string huge = PathOf("huge.yaml");
  std::ofstream(huge).close();
  fs::resize_file(huge, std::uintmax_t{2} << 30);  // sparse: no disk used
  const std::vector<std::string> errors = LoaderErrors(huge);
  EXPECT_EQ(errors[0], huge + ": is 2147483648 bytes; a scenario file is at most 1048576 bytes (1 MiB)");
  EXPECT_EQ(errors[1], huge + ": is 2147483648 bytes; a preset file is at most 1048576 bytes (1 MiB)");
  EXPECT_EQ(errors[2], huge + ": is 2147483648 bytes; a family file is at most 1048576 bytes (1 MiB)");
  for (const std::string& e : LoaderErrors(PathOf("missing.yaml"))) {
    EXPECT_NE(e.find("missing.yaml: cannot open the "), std::string::npos) << e;
    EXPECT_NE(e.find("(No such file or directory)"), std::string::npos) << e;
  }
}

TEST(ScenarioNameTest, ANameIsANameNeverAPath) {
  for (const char* good : {"carport_2p5", "a", "slope-20.v2", "carport_height_007", "A_B-c.d"}) {
    EXPECT_EQ(NameProblem(good), "") << good;
  }
  EXPECT_EQ(NameProblem(std::string(100, 'a')), "");
  EXPECT_EQ(NameProblem(std::string(101, 'a')), "is 101 bytes long (at most 100)");
  EXPECT_EQ(NameProblem(""), "is empty");
  EXPECT_EQ(NameProblem("."), "starts with '.'");
  EXPECT_EQ(NameProblem(".."), "starts with '.'");
  EXPECT_EQ(NameProblem(".hidden"), "starts with '.'");
  EXPECT_EQ(NameProblem("/tmp/x"), "holds '/' (a name is not a path)");
  EXPECT_EQ(NameProblem("../up"), "starts with '.'");
  EXPECT_EQ(NameProblem("a/../b"), "holds '/' (a name is not a path)");
  EXPECT_EQ(NameProblem("a,b"), "holds ','");
  EXPECT_EQ(NameProblem("a b"), "holds '\\x20'");
  EXPECT_EQ(NameProblem("a\nb"), "holds '\\x0a'");
  EXPECT_EQ(NameProblem("caf\xc3\xa9"), "holds '\\xc3'");
  EXPECT_EQ(NameProblem("a\\b"), "holds '\\'");
  const std::string base = "time_limit_s: 5\nterrain: {kind: flat, size_m: [40, 20]}\nroute: [[0, 0], [5, 0]]\n";
  EXPECT_EQ(ErrorOf("name: \"..\"\n" + base),
            "test.yaml:1: name '..' starts with '.'; a name is 1 to 100 ASCII letters, digits, '_', '-' and '.', not starting "
            "with '.'");
  EXPECT_EQ(ErrorOf("description: x\nname: /some/dir\n" + base).rfind("test.yaml:2: name '/some/dir' holds '/'", 0), 0u);
  EXPECT_EQ(ErrorOf("name: " + std::string(300, 'n') + "\n" + base).rfind("test.yaml:1: name 'nnnnn", 0), 0u);
  EXPECT_NE(ErrorOf("name: ok\n" + base, {"name=.."}).find("name '..' starts with '.'"), std::string::npos)
      << ErrorOf("name: ok\n" + base, {"name=.."});
  EXPECT_EQ(ErrorOf("name: a-b.c_2\n" + base), "");
}

// A range check names the file, the line of the key it refuses and the key.
TEST(ScenarioValidationTest, RangeChecksNameTheLineOfTheirKey) {
  const std::string head = "name: b\ntime_limit_s: 5\nterrain: {kind: flat, size_m: [40, 20]}\n";
  const std::string route = "route: [[0, 0], [5, 0]]\n";
  EXPECT_EQ(LoadError(head + "route: [[0, 0]]\n").rfind("bad.yaml:4: 'route' must be a list of two or more [x, y] waypoints", 0), 0u)
      << LoadError(head + "route: [[0, 0]]\n");
  EXPECT_EQ(LoadError(head + "route:\n  - [1, 1]\n  - [1, 1]\n").rfind("bad.yaml:5: route has no length", 0), 0u)
      << LoadError(head + "route:\n  - [1, 1]\n  - [1, 1]\n");
  EXPECT_EQ(LoadError(head + "route:\n  - [0, 0]\n  - [5, 0]\n  - [50, 0]\n").rfind("bad.yaml:7: route[2] lies off the terrain", 0), 0u)
      << LoadError(head + "route:\n  - [0, 0]\n  - [5, 0]\n  - [50, 0]\n");
  EXPECT_EQ(LoadError("name: b\ntime_limit_s: .inf\n" + route).rfind("bad.yaml:2: time_limit_s must be in (0, 86400] s", 0), 0u);
  const std::string ramp = "name: b\ntime_limit_s: 5\nterrain:\n  kind: ramp\n  ramp:\n    height_m: 1\n    angle_deg: 95\n" + route;
  EXPECT_EQ(LoadError(ramp).rfind("bad.yaml:7: in 'terrain': TerrainConfig: ramp.angle_deg must be in (0, 80)", 0), 0u)
      << LoadError(ramp);
  const std::string box = head + route + "objects:\n  - cylinder: {x_m: 3, y_m: 3}\n  - box:\n      x_m: 1\n      y_m: 1\n      length_m: -2\n";
  EXPECT_EQ(LoadError(box).rfind("bad.yaml:10: in 'objects[1].box': length_m must be > 0", 0), 0u) << LoadError(box);
  const std::string sensor = head + route + "sensor:\n  range_sigma_m: 0.01\n  dropout_fraction: 2\n";
  EXPECT_EQ(LoadError(sensor).rfind("bad.yaml:7: in 'sensor': Vlp16Sim::Config: dropout_fraction must be in [0, 1]", 0), 0u)
      << LoadError(sensor);
  const std::string odometry = head + route + "odometry:\n  noise_xy_m: 0.1\n  noise_z_m: -1\n";
  EXPECT_EQ(LoadError(odometry).rfind("bad.yaml:7: in 'odometry': ", 0), 0u) << LoadError(odometry);
  const std::string goal = head + route + "criteria:\n  goal:\n    x_m: 5\n    y_m: 0\n    radius_m: 1000\n";
  EXPECT_EQ(LoadError(goal).rfind("bad.yaml:9: criteria.goal.radius_m must be at most 100 m", 0), 0u) << LoadError(goal);
  // A speed no ground vehicle drives is refused, at its line.
  const std::string fast = head + route + "navigator:\n  follower:\n    lookahead_min_m: 1\n    target_speed_mps: 1e308\n";
  EXPECT_EQ(LoadError(fast).rfind("bad.yaml:8: in 'navigator.follower': PurePursuit::Config: target_speed_mps must be in (0, 30] m/s, "
                                  "got 1e+308", 0),
            0u)
      << LoadError(fast);
  EXPECT_NE(ErrorOf(head + route, {"navigator.follower.target_speed_mps=31"}).find("target_speed_mps must be in (0, 30] m/s"),
            std::string::npos);
}

}  // namespace
}  // namespace ovpc::scenarios
