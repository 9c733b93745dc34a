// Subcommands of the `ovpc` command line. Each Register* adds a subcommand to the app and returns
// the function that runs it after parsing (returning the process exit code).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "ovpc/suite/runner.h"

namespace ovpc::apps {

/// Exit codes shared by all subcommands.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   ///< the job ran but failed (or could not write its output)
inline constexpr int kExitBadInput = 2;  ///< bad arguments or input data

/// Bad input given by the user: printed as one line, exit code 2.
class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using Runner = std::function<int()>;

/// `--map NAME` of `ovpc run` and `ovpc suite`: "navigator.map=NAME", or bad input.
using suite::MapSetting;

/// A validator for a path option given with no text (`--out ''`, `--preset ''`).
inline CLI::Validator NotEmpty() {
  return CLI::Validator([](std::string& value) { return value.empty() ? std::string("must name a file or folder, got ''") : std::string(); },
                        "NOT EMPTY");
}

Runner RegisterMesh(CLI::App& app);
Runner RegisterSynth(CLI::App& app);
Runner RegisterRun(CLI::App& app);
Runner RegisterSuite(CLI::App& app);
Runner RegisterFamily(CLI::App& app);
Runner RegisterMerge(CLI::App& app);
Runner RegisterCompare(CLI::App& app);

}  // namespace ovpc::apps
