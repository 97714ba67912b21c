// `rtusim sweep SPEC [--set …] --out DIR [--threads N] [--scheduler tcp://HOST:PORT]`: every
// point of a sweep spec (sim/app/sweep_plan.h), resumable, into DIR/results.csv; the plots
// by scripts/sweep_plot.py when Python with matplotlib is at hand. The hidden `--group K` runs
// one job of the plan (what the local runner and the Dask workers start).
#include <chrono>
#include <filesystem>
#include <optional>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/set_option.h"
#include "app/sweep_job.h"
#include "app/sweep_runner.h"
#include "app/thread_count_option.h"
#include "util/error.h"

namespace rtusim {
namespace {

struct SweepOptions {
  SweepRunOptions run;
  std::string out;
  long group = -1;
  bool no_plots = false;
};

SweepOptions& options() {
  static SweepOptions o;
  return o;
}

// --scheduler: [SCHEME://]HOST:PORT, checked before the sweep makes anything.
void check_scheduler_address(const std::string& address) {
  const size_t scheme = address.find("://");
  const std::string host_port = scheme == std::string::npos ? address : address.substr(scheme + 3);
  const size_t colon = host_port.rfind(':');
  const std::string port = colon == std::string::npos ? "" : host_port.substr(colon + 1);
  const bool digits = !port.empty() && port.size() <= 5 &&
                      port.find_first_not_of("0123456789") == std::string::npos;
  if (colon == 0 || !digits || std::stoul(port) == 0 || std::stoul(port) > 65535)
    throw InputError("--scheduler " + address + ": expected tcp://HOST:PORT");
}

// The sweep's directory; one that cannot be made is bad input (the --out given).
SweepDir open_sweep_dir(const std::string& out, const SweepPlan& plan) {
  try {
    return SweepDir(out, plan);
  } catch (const std::filesystem::filesystem_error& e) {
    throw InputError("--out " + out + ": cannot make the sweep's directory (" +
                     e.code().message() + ")");
  }
}

}  // namespace

CLI::App* add_sweep_subcommand(CLI::App& app) {
  SweepOptions& o = options();
  auto* cmd = app.add_subcommand("sweep", "Sweep a run config over a [sweep] table of keys");
  cmd->add_option("spec", o.run.spec, "TOML sweep spec: a run config plus [sweep]")->required();
  add_set_option(cmd, o.run.sets, "Override a base config key");
  cmd->add_option("--out", o.out, "Output directory (resumable)")->required();
  cmd->add_option("--threads", o.run.threads, "Jobs at once (default: all cores)")
      ->check(thread_count());
  cmd->add_option("--scheduler", o.run.scheduler, "Dask scheduler address (tcp://HOST:PORT)");
  cmd->add_flag("--no-plots", o.no_plots, "Do not draw the plots");
  cmd->add_option("--group", o.group, "Run one job of the plan (used by the runners)")
      ->group("");
  return cmd;
}

int sweep_command() {
  namespace fs = std::filesystem;
  SweepOptions o = options();
  const auto t0 = std::chrono::steady_clock::now();
  // A runner's job plans again without loading scenes: the sweep checked them once.
  const SweepPlan plan = plan_sweep(o.run.spec, o.run.sets, /*check_scenes=*/o.group < 0);
  if (o.group >= 0 && static_cast<size_t>(o.group) >= plan.jobs.size())
    throw InputError("--group " + std::to_string(o.group) + ": the sweep has " +
                     std::to_string(plan.jobs.size()) + " jobs");
  if (o.group >= 0) {
    // One job, started by a runner: its bad input named by the spec and the job's keys.
    const SweepDir dir(o.out, plan);
    const unsigned threads = o.run.threads ? o.run.threads : std::thread::hardware_concurrency();
    nlohmann::json rows;
    try {
      rows = run_sweep_job(plan, o.group, dir.base_config(), std::max(1u, threads));
    } catch (const InputError& e) {
      throw InputError(job_error(plan, o.group, dir.base_config(), e.what()));
    }
    dir.write_job(o.group, rows);
    return 0;
  }
  if (!o.run.scheduler.empty()) check_scheduler_address(o.run.scheduler);
  // The jobs read the spec from wherever they start (a Dask worker's own directory).
  o.run.spec = fs::absolute(o.run.spec).lexically_normal().string();
  // The directories this sweep makes (--out and any missing parents) are removed again if bad
  // input stops it before any job finished: nothing is left of a sweep that could not run. A
  // finished job's rows, or a directory that held the sweep before, stay.
  std::error_code ec;
  fs::path made = fs::absolute(o.out, ec).lexically_normal();
  if (made.filename().empty()) made = made.parent_path();  // a trailing '/'
  if (fs::exists(made, ec)) {
    made.clear();
  } else {
    while (made.has_parent_path() && made.parent_path() != made &&
           !fs::exists(made.parent_path(), ec))
      made = made.parent_path();
  }
  const auto discard = [&] {
    if (made.empty()) return;
    const fs::path jobs = fs::path(o.out) / "jobs";
    if (fs::is_directory(jobs, ec) && !fs::is_empty(jobs, ec)) return;
    fs::remove_all(made, ec);
  };
  std::optional<SweepDir> dir;
  std::vector<size_t> pending;
  int rc = 0;
  try {
    dir.emplace(open_sweep_dir(o.out, plan));
    pending = pending_sweep_jobs(plan, *dir);
    rc = run_sweep_jobs(plan, *dir, o.run, pending);
  } catch (const InputError&) {
    discard();
    throw;
  }
  if (rc == 2) discard();
  if (rc != 0) return rc;
  dir->write_results(plan);
  std::printf("rtusim sweep %s -> %s/results.csv: %zu points in %zu jobs (%zu done before), "
              "%.1f s\n",
              options().run.spec.c_str(), o.out.c_str(), plan.points.size(), plan.jobs.size(),
              plan.jobs.size() - pending.size(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  if (!o.no_plots) draw_sweep_plots(o.out);
  return 0;
}

}  // namespace rtusim
