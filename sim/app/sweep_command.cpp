// `rtusim sweep SPEC [--set …] --out DIR [--threads N] [--scheduler tcp://HOST:PORT]`: every
// point of a sweep spec (sim/app/sweep_plan.h), resumable, into DIR/results.csv; the plots
// by scripts/sweep_plot.py when Python with matplotlib is at hand. The hidden `--group K` runs
// one job of the plan (what the local runner and the Dask workers start).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/sweep_job.h"
#include "app/sweep_runner.h"
#include "util/error.h"

namespace rtusim {
namespace {

struct SweepOptions {
  SweepRunOptions run;
  std::string out;
  long group = -1;
  bool plots = true;
};

SweepOptions& options() {
  static SweepOptions o;
  return o;
}

}  // namespace

CLI::App* add_sweep_subcommand(CLI::App& app) {
  SweepOptions& o = options();
  auto* cmd = app.add_subcommand("sweep", "Sweep a run config over a [sweep] table of keys");
  cmd->add_option("spec", o.run.spec, "TOML sweep spec: a run config plus [sweep]")->required();
  cmd->add_option("--set", o.run.sets, "Override a base config key: KEY=VALUE")
      ->allow_extra_args(false);
  cmd->add_option("--out", o.out, "Output directory (resumable)")->required();
  cmd->add_option("--threads", o.run.threads, "Jobs at once (default: all cores)")
      ->check(CLI::Range(1u, 4096u));
  cmd->add_option("--scheduler", o.run.scheduler, "Dask scheduler address (tcp://HOST:PORT)");
  cmd->add_flag("!--no-plots", o.plots, "Do not draw the plots");
  cmd->add_option("--group", o.group, "Run one job of the plan (used by the runners)")
      ->group("");
  return cmd;
}

int sweep_command() {
  const SweepOptions& o = options();
  const auto t0 = std::chrono::steady_clock::now();
  const SweepPlan plan = plan_sweep(o.run.spec, o.run.sets);
  if (o.group >= 0 && static_cast<size_t>(o.group) >= plan.jobs.size())
    throw InputError("--group " + std::to_string(o.group) + ": the sweep has " +
                     std::to_string(plan.jobs.size()) + " jobs");
  const SweepDir dir(o.out, plan);
  if (o.group >= 0) {
    const unsigned threads = o.run.threads ? o.run.threads : std::thread::hardware_concurrency();
    dir.write_job(o.group, run_sweep_job(plan, o.group, dir.base_config(), std::max(1u, threads)));
    return 0;
  }
  const std::vector<size_t> pending = pending_sweep_jobs(plan, dir);
  const size_t skipped = plan.jobs.size() - pending.size();
  if (const int rc = run_sweep_jobs(plan, dir, o.run, pending); rc != 0) return rc;
  dir.write_results(plan);
  std::printf("rtusim sweep %s -> %s/results.csv: %zu points in %zu jobs (%zu done before), "
              "%.1f s\n",
              o.run.spec.c_str(), o.out.c_str(), plan.points.size(), plan.jobs.size(), skipped,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  if (o.plots) draw_sweep_plots(o.out);
  return 0;
}

}  // namespace rtusim
