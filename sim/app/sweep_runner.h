// Runs the pending jobs of a sweep, each as a child process `rtusim sweep SPEC --group K --out
// DIR` (SystemC keeps global state, and a crash or kill loses one job at most): up to `threads`
// at once on this machine, or as Dask tasks through scripts/sweep_dask.py when a scheduler
// address is given. A progress bar (points done / total, elapsed, remaining) on a terminal.
#pragma once
#include <string>
#include <vector>

#include "app/sweep_dir.h"
#include "app/sweep_plan.h"

namespace rtusim {

struct SweepRunOptions {
  std::string spec;
  std::vector<std::string> sets;
  unsigned threads = 0;   // 0 = all cores
  std::string scheduler;  // tcp://HOST:PORT: Dask; empty: local
};

// The jobs of `plan` without a file in `dir` (not finished), in increasing order.
std::vector<size_t> pending_sweep_jobs(const SweepPlan& plan, const SweepDir& dir);

// Runs the `pending` jobs (pending_sweep_jobs()). Returns 0, or the exit status of the first
// failed job (2 for bad input, 1 otherwise) after printing its last log line.
int run_sweep_jobs(const SweepPlan& plan, const SweepDir& dir, const SweepRunOptions& opts,
                   const std::vector<size_t>& pending);

// Runs scripts/sweep_plot.py on DIR/results.csv (Python from $RTUSIM_PYTHON, the project's .venv
// or python3); says so and goes on when it cannot (the table is the result, the plots a view).
void draw_sweep_plots(const std::string& dir);

}  // namespace rtusim
