// Running a suite's jobs: each as `ovpc run` in a process group of its own, --jobs at a time, the
// longest first; SIGINT and SIGTERM stop them.
#pragma once

#include <vector>

#include "ovpc/suite/report.h"
#include "ovpc/suite/runner.h"

namespace ovpc::suite {

/// Runs every job that is not already an error, fills in its result (and a family run's verdict),
/// and prints progress. Returns the signal that stopped the suite (0: none); the jobs it did not
/// finish are then errors ("cancelled: ...").
int RunJobs(std::vector<Job>& jobs, const Options& options, const std::vector<FamilyInput>& families);

}  // namespace ovpc::suite
