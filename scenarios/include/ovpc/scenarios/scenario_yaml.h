// Scenario files: YAML (yaml-cpp) into Scenario, strictly. The schema is in scenarios/README.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "ovpc/scenarios/scenario.h"

namespace ovpc::scenarios {

/// A malformed scenario: unknown key, wrong type, missing field, bad value. what() is one line,
/// "FILE:LINE: ..." naming the key.
class ScenarioError : public std::runtime_error {
 public:
  /// Control characters in `what` (from a key or value of the file, or in yaml-cpp's own message,
  /// which can end in the raw character it could not read) are shown as \xHH, so what() is always
  /// one line.
  explicit ScenarioError(const std::string& what);
};

/// The largest scenario, family or preset file read: 1 MiB (the largest bundled one is under 20 KB).
constexpr std::uintmax_t kMaxScenarioFileBytes = std::uintmax_t{1} << 20;

/// The bytes of the regular file `path` of at most `max_bytes`. Anything else is refused before a
/// byte is read and without blocking: a missing file, a directory, a FIFO, a socket or a device
/// (/dev/zero), a larger file. `what` names the kind of file in messages ("scenario file").
/// @throws ScenarioError, one line "PATH: problem", e.g. "x.yaml: is a directory, not a scenario
/// file", "x.yaml: is not a regular file (a FIFO)", "x.yaml: is 2147483648 bytes; a scenario file
/// is at most 1048576 bytes (1 MiB)".
std::string ReadSmallRegularFile(const std::string& path, const std::string& what,
                                 std::uintmax_t max_bytes = kMaxScenarioFileBytes);

/// Scenario and family names are used as folder and file names of runs, so a name is a name, never
/// a path: 1 to kMaxNameBytes bytes of ASCII letters, digits, '_', '-' and '.', not starting with
/// '.' (so never "." or ".."), no '/', no space, no comma, no control character. A family's name
/// is at most kMaxFamilyNameBytes, so that its draws' names (<family>_<index>) are names too.
constexpr std::size_t kMaxNameBytes = 100;
constexpr std::size_t kMaxFamilyNameBytes = 64;

/// What is wrong with `name` as a scenario or family name ("starts with '.'", ...), or "" when it
/// is one.
std::string NameProblem(const std::string& name, std::size_t max_bytes = kMaxNameBytes);

/// @throws ScenarioError "FILE:LINE: name '...' problem; a name is ..." (no line when `line` <= 0)
/// unless `name` is a valid name.
void ValidateName(const std::string& file, int line, const std::string& name, std::size_t max_bytes = kMaxNameBytes);

/// The robot's configuration a scenario starts from: YAML with a `navigator:` section (the keys the
/// Configs declare in their VisitFields), optionally the testbed's `record:` section (the default
/// preset has none: Recording::Config's defaults hold), and the file name that errors give.
struct Preset {
  std::string yaml;
  std::string file;
};

/// navigation/presets/default.yaml, the closed-loop defaults, as built into the program.
Preset DefaultPreset();
/// A preset file (a copy of the default one, edited).
/// @throws ScenarioError if it cannot be read.
Preset LoadPreset(const std::string& path);

/// Reads a scenario file over `preset`. `settings` are "dotted.key=value" overrides applied to the
/// scenario's YAML before it is read (`ovpc run --set`, `ovpc suite --sweep`), e.g.
/// "navigator.ovpc.mapper.ghpr.gamma=-0.02".
/// @throws ScenarioError (a malformed scenario or preset).
Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings = {},
                      const Preset& preset = DefaultPreset());

/// The same from YAML text (tests); `name_for_errors` stands for the file in messages.
Scenario ParseScenario(const std::string& yaml_text, const std::string& name_for_errors,
                       const std::vector<std::string>& settings = {}, const Preset& preset = DefaultPreset());

/// The effective configuration of a run of `scenario` with `seed` as YAML (`navigator:`, then the
/// testbed's `record:`): what `ovpc run --print-config` prints; a valid preset itself.
std::string FormatRunConfig(const Scenario& scenario);

}  // namespace ovpc::scenarios
