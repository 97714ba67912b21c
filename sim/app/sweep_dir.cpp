#include "app/sweep_dir.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "util/error.h"
#include "util/output_files.h"
#include "util/read_text_file.h"

namespace rtusim {
namespace {

namespace fs = std::filesystem;

// The file's text; empty when it cannot be read (then it does not parse).
std::string read_text(const fs::path& p) { return read_text_file(p).value_or(""); }

// Writes `text` to `path` through an OutputFile: a temporary file (removed if a signal stops
// the process) renamed over `path`, so a reader sees the old file or the whole new one.
void write_file_atomically(const fs::path& path, const std::string& text) {
  OutputFile file(path);
  {
    std::ofstream out(file.temp_path(), std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw InputError(file.name() + ": cannot write (" + std::strerror(errno) + ")");
  }
  file.commit();
}

nlohmann::json identity(const SweepPlan& plan) {
  return {{"spec", plan.spec_text}, {"set", plan.sets}};
}

// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// One CSV line of fields.
std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) {
    if (i) line += ',';
    line += csv_field(fields[i]);
  }
  return line + "\n";
}

std::string json_cell(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  return v.dump();
}

}  // namespace

SweepDir::SweepDir(fs::path dir, const SweepPlan& plan) : dir_(std::move(dir)) {
  for (const SweepJob& j : plan.jobs) job_points_.push_back(j.points);
  const fs::path id_file = dir_ / "sweep.json";
  std::error_code ec;
  if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec))
    throw InputError(dir_.string() + ": exists and is not a directory");
  const nlohmann::json id = identity(plan);
  if (fs::exists(id_file)) {
    nlohmann::json held;
    try {
      held = nlohmann::json::parse(read_text(id_file));
    } catch (const nlohmann::json::exception&) {
      throw InputError(id_file.string() + ": not a sweep identity file");
    }
    if (held != id)
      throw InputError(dir_.string() + ": holds a different sweep (its sweep.toml or --set differ "
                       "from " + plan.spec_path + "); use another --out or remove it");
  } else if (fs::exists(dir_) && !fs::is_empty(dir_)) {
    throw InputError(dir_.string() + ": exists and holds no sweep; use an empty or new --out");
  }
  // The identity first: a directory killed while being set up is still recognised.
  fs::create_directories(dir_);
  if (!fs::exists(id_file)) write_file_atomically(id_file, id.dump(2) + "\n");
  fs::create_directories(dir_ / "jobs");
  fs::create_directories(dir_ / "logs");
  if (!fs::exists(dir_ / "sweep.toml")) write_file_atomically(dir_ / "sweep.toml", plan.spec_text);
  if (!fs::exists(dir_ / "base.toml")) write_file_atomically(dir_ / "base.toml", plan.base_toml);
}

fs::path SweepDir::job_file(size_t job) const {
  return dir_ / "jobs" / (std::to_string(job) + ".json");
}
fs::path SweepDir::log_file(size_t job) const {
  return dir_ / "logs" / (std::to_string(job) + ".log");
}
std::optional<nlohmann::json> SweepDir::read_job(size_t job) const {
  std::error_code ec;
  if (!fs::is_regular_file(job_file(job), ec)) return std::nullopt;
  try {
    nlohmann::json j = nlohmann::json::parse(read_text(job_file(job)));
    const nlohmann::json& rows = j.at("rows");
    if (!rows.is_object() || rows.size() != job_points_.at(job).size() ||
        !j.at("seconds").is_number() || !j.at("points").is_number())
      return std::nullopt;
    for (const size_t point : job_points_.at(job)) {  // every run writes dram.bytes.total
      const auto row = rows.find(std::to_string(point));
      if (row == rows.end() || !row->is_object() || !row->contains("dram.bytes.total"))
        return std::nullopt;
    }
    return j;
  } catch (const std::exception&) {  // not JSON, or a key missing: not done
    return std::nullopt;
  }
}

void SweepDir::write_job(size_t job, const nlohmann::json& rows) const {
  write_file_atomically(job_file(job), rows.dump() + "\n");
}

void SweepDir::write_results(const SweepPlan& plan) const {
  std::vector<nlohmann::json> rows(plan.points.size());
  std::set<std::string> stats_keys;
  std::ostringstream timings;
  timings << "job,points,layouts,alone,seconds\n";  // alone: one point run by simulate()
  for (size_t j = 0; j < plan.jobs.size(); ++j) {
    const std::optional<nlohmann::json> read = read_job(j);
    if (!read) throw std::runtime_error("sweep: job " + std::to_string(j) + " is not done");
    const nlohmann::json& job = *read;
    std::set<std::string> layouts;
    for (const auto& [index, row] : job.at("rows").items()) {
      rows.at(std::stoul(index)) = row;
      for (const auto& [k, v] : row.items()) stats_keys.insert(k);
      layouts.insert(plan.points.at(std::stoul(index)).layout);
    }
    std::string layout_list;
    for (const auto& l : layouts) {
      if (!layout_list.empty()) layout_list += ' ';
      layout_list += l;
    }
    timings << j << "," << job.at("points").get<size_t>() << "," << layout_list << ","
            << (plan.jobs[j].alone ? 1 : 0) << "," << job.at("seconds").get<double>() << "\n";
  }
  for (const auto& c : plan.columns) stats_keys.erase(c);  // the swept column stands for it
  std::ostringstream csv;
  std::vector<std::string> header = plan.columns;
  header.insert(header.end(), stats_keys.begin(), stats_keys.end());
  csv << csv_line(header);
  for (size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].is_null()) throw std::runtime_error("sweep: no row for point " + std::to_string(i));
    std::vector<std::string> fields = plan.points[i].cells;
    for (const auto& k : stats_keys)
      fields.push_back(rows[i].contains(k) ? json_cell(rows[i][k]) : "");
    csv << csv_line(fields);
  }
  write_file_atomically(dir_ / "results.csv", csv.str());
  write_file_atomically(dir_ / "timings.csv", timings.str());
}

}  // namespace rtusim
