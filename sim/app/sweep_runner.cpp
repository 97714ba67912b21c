#include "app/sweep_runner.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <thread>

#ifndef RTUSIM_SOURCE_DIR
#define RTUSIM_SOURCE_DIR "."
#endif

extern char** environ;

namespace rtusim {
namespace {

namespace fs = std::filesystem;

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("rtusim") : p.string();
}

// Starts `argv` with stdout and stderr to `log` (empty: inherited). Returns the pid.
pid_t spawn(const std::vector<std::string>& argv, const std::string& log) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  if (!log.empty()) {
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
  }
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("cannot start " + argv[0]);
  return pid;
}

std::string last_line(const fs::path& p) {
  std::ifstream in(p);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

std::vector<std::string> job_command(const SweepRunOptions& o, const SweepDir& dir) {
  std::vector<std::string> argv = {self_exe(), "sweep", o.spec};
  for (const auto& s : o.sets) argv.insert(argv.end(), {"--set", s});
  argv.insert(argv.end(), {"--out", dir.path().string()});
  return argv;
}

// The progress bar on stderr: points done / total, elapsed, remaining.
class Progress {
 public:
  Progress(size_t total, size_t done)
      : total_(total), done_(done), start_done_(done), enabled_(::isatty(2) != 0),
        start_(std::chrono::steady_clock::now()) {}
  void add(size_t points) { done_ += points; }
  void draw(bool final = false) {
    if (!enabled_) return;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const size_t fresh = done_ - start_done_;
    const double rest = fresh > 0 ? elapsed * double(total_ - done_) / double(fresh) : -1.0;
    const int width = 30, filled = total_ ? int(width * done_ / total_) : width;
    std::string bar(filled, '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\rsweep [%s] %zu/%zu points  elapsed %s  remaining %s   ", bar.c_str(),
                 done_, total_, clock_text(elapsed).c_str(),
                 rest < 0 ? "?" : clock_text(rest).c_str());
    if (final) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }

 private:
  static std::string clock_text(double s) {
    const long t = long(s + 0.5);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
    return buf;
  }
  size_t total_, done_, start_done_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
};

int exit_status(int wait_status) {
  return WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : 128 + WTERMSIG(wait_status);
}

// The job's failure, reported once: 2 stays 2 (bad input: the job's own line, which names the
// spec and the job), anything else is 1 (with its log).
int report_failure(size_t job, int status, const SweepDir& dir) {
  const std::string line = last_line(dir.log_file(job));
  if (status == 2 && line.rfind("rtusim: ", 0) == 0) {
    std::fprintf(stderr, "%s\n", line.c_str());
    return 2;
  }
  std::fprintf(stderr, "rtusim: sweep job %zu failed (exit %d): %s (log: %s)\n", job, status,
               line.c_str(), dir.log_file(job).c_str());
  return status == 2 ? 2 : 1;
}

int run_local(const SweepPlan& plan, const SweepDir& dir, const SweepRunOptions& o,
              std::vector<size_t> pending, Progress& progress) {
  const unsigned threads = o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
  std::map<pid_t, size_t> running;
  size_t next = 0;
  int failed = 0;
  while (next < pending.size() || !running.empty()) {
    while (!failed && next < pending.size() && running.size() < threads) {
      const size_t job = pending[next++];
      // The cores left over when there are fewer jobs than cores go to the jobs' caches.
      const size_t per_job = std::max<size_t>(1, threads / std::min<size_t>(threads, pending.size()));
      std::vector<std::string> argv = job_command(o, dir);
      argv.insert(argv.end(), {"--group", std::to_string(job), "--threads", std::to_string(per_job)});
      running[spawn(argv, dir.log_file(job).string())] = job;
    }
    if (failed && running.empty()) break;
    int st = 0;
    const pid_t pid = ::waitpid(-1, &st, WNOHANG);
    if (pid <= 0) {
      progress.draw();
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      continue;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const size_t job = it->second;
    running.erase(it);
    const int status = exit_status(st);
    if (status == 0 && dir.job_done(job)) {
      progress.add(plan.jobs[job].points.size());
    } else if (!failed) {
      progress.draw(true);
      failed = report_failure(job, status, dir);
    }
  }
  return failed;
}

std::string python() {
  if (const char* p = std::getenv("RTUSIM_PYTHON"); p && *p) return p;
  const fs::path venv = fs::path(RTUSIM_SOURCE_DIR) / ".venv" / "bin" / "python";
  return fs::exists(venv) ? venv.string() : "/usr/bin/python3";
}

int run_dask(const SweepPlan& plan, const SweepDir& dir, const SweepRunOptions& o,
             const std::vector<size_t>& pending) {
  std::vector<std::string> argv = {python(),
                                   (fs::path(RTUSIM_SOURCE_DIR) / "scripts" / "sweep_dask.py").string(),
                                   "--scheduler", o.scheduler, "--jobs"};
  std::string list;
  for (const size_t j : pending) {
    if (!list.empty()) list += ',';
    list += std::to_string(j);
  }
  argv.push_back(list);
  argv.push_back("--");
  for (const auto& a : job_command(o, dir)) argv.push_back(a);
  int st = 0;
  ::waitpid(spawn(argv, ""), &st, 0);
  const int status = exit_status(st);
  if (status == 2) return 2;  // bad input: the driver said what, in one line
  if (status != 0) {
    std::fprintf(stderr, "rtusim: sweep: the Dask driver failed (exit %d)\n", status);
    return 1;
  }
  for (const size_t j : pending)
    if (!dir.job_done(j)) return report_failure(j, 1, dir);
  (void)plan;
  return 0;
}

}  // namespace

void draw_sweep_plots(const std::string& dir) {
  const std::string log = (fs::path(dir) / "logs" / "plots.log").string();
  int st = 0;
  try {
    ::waitpid(spawn({python(), (fs::path(RTUSIM_SOURCE_DIR) / "scripts" / "sweep_plot.py").string(),
                     dir},
                    log),
              &st, 0);
  } catch (const std::exception&) {
    st = 1 << 8;
  }
  if (exit_status(st) == 0) std::printf("  plots: %s\n", last_line(log).c_str());
  else std::printf("  plots skipped (%s)\n", last_line(log).c_str());
}

std::vector<size_t> pending_sweep_jobs(const SweepPlan& plan, const SweepDir& dir) {
  std::vector<size_t> pending;
  for (size_t j = 0; j < plan.jobs.size(); ++j)
    if (!dir.job_done(j)) pending.push_back(j);
  return pending;
}

int run_sweep_jobs(const SweepPlan& plan, const SweepDir& dir, const SweepRunOptions& opts,
                   const std::vector<size_t>& pending) {
  size_t done_points = plan.points.size();
  for (const size_t j : pending) done_points -= plan.jobs[j].points.size();
  if (!opts.scheduler.empty()) return run_dask(plan, dir, opts, pending);
  Progress progress(plan.points.size(), done_points);
  progress.draw();
  const int rc = run_local(plan, dir, opts, pending, progress);
  if (rc == 0) progress.draw(true);
  return rc;
}

}  // namespace rtusim
