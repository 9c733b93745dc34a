// A suite's result file: summary.json as JSON, a run's identity and the planned run list's fingerprint.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ovpc/suite/report.h"

namespace ovpc::suite {

/// summary.json of `results`, of which `passed` runs passed: the suite record, the families (with
/// their files' text) and every run (LoadSuiteResults reads it back).
nlohmann::json SummaryJson(const SuiteResults& results, std::size_t passed);

/// A run's identity, the same in every shard of a suite: what it runs (a family's file and draw for
/// a family run), its scenario, seed, settings, map, and its folder relative to the suite's `out`.
std::string RunIdentity(const Job& job, const std::vector<FamilyInput>& families, const std::string& out);

/// The fingerprint of a whole planned run list: the input files' contents, the families' texts, and
/// every run's identity (`ids`, per job) and time limit, in the planned order.
std::string PlanFingerprint(const std::vector<std::string>& files, const std::vector<FamilyInput>& families,
                            const std::vector<Job>& jobs, const std::vector<std::string>& ids);

}  // namespace ovpc::suite
