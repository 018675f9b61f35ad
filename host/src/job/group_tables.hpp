// Internal: how a job's tables become bakes, shared by run_job and estimate_job (brdfbake/job.hpp,
// brdfbake/plan.hpp), so that an estimate measures exactly the bakes the run makes.
#pragma once

#include <cstddef>
#include <vector>

#include "brdfbake/job.hpp"

namespace brdfbake::detail {

// The job's defaults made explicit in its tables (the job's device where a table names none, the
// job's environment where a table that reads one names none), then identical tables grouped
// (table_bake_key): each group, the indices of its tables in the job's order, is baked once; groups
// in the order of their first table.
std::vector<std::vector<size_t>> group_tables(Job& job);

}  // namespace brdfbake::detail
