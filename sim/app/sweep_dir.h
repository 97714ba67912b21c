// The output directory of a sweep, and what makes it resumable:
//   sweep.toml   the spec as given;  sweep.json  what identifies the sweep (spec text, --set)
//   base.toml    the base config every point runs on
//   jobs/K.json  the rows of finished job K, each written atomically (OutputFile)
//   logs/K.log   what job K printed;  results.csv, timings.csv  when every job is done
// A rerun with the same spec skips the jobs whose file holds a row for each of their points (a
// damaged or partial file is run again); a different spec in a directory that holds a sweep is
// an InputError.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/sweep_plan.h"

namespace rtusim {

class SweepDir {
 public:
  // Creates the directory and its identity files, or checks that they match `plan`.
  SweepDir(std::filesystem::path dir, const SweepPlan& plan);

  const std::filesystem::path& path() const { return dir_; }
  std::string base_config() const { return (dir_ / "base.toml").string(); }
  std::filesystem::path job_file(size_t job) const;
  std::filesystem::path log_file(size_t job) const;
  // Job `job`'s file, parsed, when it holds a row for each of the job's points; else nullopt.
  std::optional<nlohmann::json> read_job(size_t job) const;
  bool job_done(size_t job) const { return read_job(job).has_value(); }
  void write_job(size_t job, const nlohmann::json& rows) const;

  // results.csv (one row per point: the swept keys, then every stats key in sorted order) and
  // timings.csv (seconds per job), from the job files. Throws if a job is missing.
  void write_results(const SweepPlan& plan) const;

 private:
  std::filesystem::path dir_;
  std::vector<std::vector<size_t>> job_points_;  // each job's points, from the plan
};

}  // namespace rtusim
