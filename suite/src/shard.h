// Sharding a suite: which shard runs each planned run.
#pragma once

#include <string>
#include <vector>

#include "ovpc/suite/report.h"

namespace ovpc::suite {

/// The shard (1..shards) of each planned job: longest-processing-time-first greedy over the whole
/// list, a job's cost its scenario's time limit. Jobs are taken by cost (highest first), equal costs
/// by identity (`ids`, per job), and each goes to the shard with the least cost so far (then the
/// fewest runs, then the lowest number). Depends on the planned list alone, never on a clock.
std::vector<int> AssignShards(const std::vector<Job>& jobs, const std::vector<std::string>& ids, int shards);

}  // namespace ovpc::suite
