// Runs one job of a sweep plan and returns its rows: the stats of each of its points, exactly
// the stats.json keys `rtusim run` writes for that point, timing keys left out.
//  - A functional job prepares the scene and tree once (every layout of the job) and traces the
//    frame once per layout through a SweepBackend that evaluates every cache configuration of
//    the job in that pass; each point's keys are written by simulate()'s and the functional
//    tier's own stats code (add_run_stats, FunctionalTier::write_stats, add_report_stats) from
//    that pass's counters. tests/cli/sweep.sh checks rows against `rtusim run`.
//  - A timed job (cycle, rtl) is one point through simulate().
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "app/sweep_plan.h"

namespace rtusim {

// {"job": K, "points": N, "seconds": S, "rows": {"<point index>": {stats key: value}}}.
// `base_path` is the base config file (the sweep's base.toml); `threads` share out the cache
// evaluation of a functional job (SweepPipeline workers).
nlohmann::json run_sweep_job(const SweepPlan& plan, size_t job, const std::string& base_path,
                             unsigned threads = 1);

}  // namespace rtusim
