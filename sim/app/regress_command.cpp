// `rtusim regress`: reruns the reference cases under traces/ in-process and compares every
// deterministic stat, and the node stream's count and checksum, with the case's expected.json.
//
// A case is a subdirectory DIR/<case>/ with config.toml and expected.json (a flat JSON object).
// Expected keys: every stats.json key of the run but the timings (is_timing_key: wall-clock
// seconds and rates; rates over simulated time are results), plus trace.node_stream.count and .checksum (of the first
// layout; with several layouts also layout.<kind>.trace.node_stream.*). Values compare exactly.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/simulation.h"
#include "app/node_stream.h"
#include "trace/trace_format.h"
#include "util/error.h"
#include "util/output_files.h"
#include "util/stat_decl.h"
#include "util/stats.h"

#ifndef RTUSIM_SOURCE_DIR
#define RTUSIM_SOURCE_DIR "."
#endif

namespace rtusim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

struct Case {
  std::string name;
  fs::path config, expected_path;
  json expected;  // null when absent (allowed only with --update)
};

// traces/ beside the project (the source tree this binary was built from), else ./traces.
fs::path default_dir() {
  const fs::path beside = fs::path(RTUSIM_SOURCE_DIR) / "traces";
  std::error_code ec;
  return fs::is_directory(beside, ec) ? beside : fs::path("traces");
}

json read_expected(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot read");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(path.string() + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw InputError(path.string() + ": expected a JSON object of stats keys");
  for (const auto& [k, v] : j.items())
    if (!(v.is_number() || v.is_string() || v.is_boolean()))
      throw InputError(path.string() + ": " + k + ": expected a number, string or boolean, got " +
                       v.type_name());
  return j;
}

// Every case of `dir`, checked before any is run.
std::vector<Case> find_cases(const fs::path& dir, bool update) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(dir.string() + ": no such directory of reference cases");
  std::vector<fs::path> subdirs;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_directory() && e.path().filename().string().front() != '.') subdirs.push_back(e.path());
  std::sort(subdirs.begin(), subdirs.end());
  std::vector<Case> cases;
  for (const fs::path& d : subdirs) {
    Case c;
    c.name = d.filename().string();
    c.config = d / "config.toml";
    c.expected_path = d / "expected.json";
    if (!fs::is_regular_file(c.config, ec))
      throw InputError(c.config.string() + ": missing: a reference case needs config.toml");
    if (fs::exists(c.expected_path, ec))
      c.expected = read_expected(c.expected_path);
    else if (!update)
      throw InputError(c.expected_path.string() +
                       ": missing (create it with rtusim regress DIR --update)");
    cases.push_back(std::move(c));
  }
  if (cases.empty())
    throw InputError(dir.string() + ": no reference cases (subdirectories with config.toml)");
  return cases;
}

// The case's deterministic results: what expected.json holds.
json run_case(const Case& c) {
  const Prepared p = prepare_run(c.config.string(), {});
  const SimulationResult r = simulate(p);
  json got = json::object();
  for (const auto& [k, v] : r.stats.values())
    if (!is_timing_key(k)) got[k] = v;
  for (size_t i = 0; i < p.images.size(); ++i) {
    const MemoryImage& image = p.images[i];
    const TraceDigest d = node_stream_digest(p, image);
    if (i == 0) {
      got["trace.node_stream.count"] = d.count;
      got["trace.node_stream.checksum"] = hex64(d.checksum);
    }
    if (p.images.size() > 1) {
      got["layout." + image.layout + ".trace.node_stream.count"] = d.count;
      got["layout." + image.layout + ".trace.node_stream.checksum"] = hex64(d.checksum);
    }
  }
  return got;
}

// Prints every mismatch between `expected` and `got` (a missing or an extra key is one);
// returns how many.
int compare(const std::string& name, const json& expected, const json& got) {
  int mismatches = 0;
  auto report = [&](const std::string& key, const std::string& e, const std::string& g) {
    std::printf("MISMATCH %s %s: expected %s, got %s\n", name.c_str(), key.c_str(), e.c_str(),
                g.c_str());
    ++mismatches;
  };
  for (const auto& [k, v] : expected.items()) {
    const auto it = got.find(k);
    if (it == got.end()) report(k, v.dump(), "(absent)");
    else if (*it != v || it->is_string() != v.is_string()) report(k, v.dump(), it->dump());
  }
  for (const auto& [k, v] : got.items())
    if (!expected.contains(k)) report(k, "(absent)", v.dump());
  return mismatches;
}

}  // namespace

int regress_command(const RegressOptions& opts) {
  const fs::path dir = opts.dir.empty() ? default_dir() : fs::path(opts.dir);
  const std::vector<Case> cases = find_cases(dir, opts.update);
  std::printf("regress: %zu cases in %s%s\n", cases.size(), dir.string().c_str(),
              opts.update ? " (updating expected.json)" : "");
  int passed = 0, failed = 0;
  for (const Case& c : cases) {
    const auto t0 = std::chrono::steady_clock::now();
    const json got = run_case(c);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (opts.update) {
      OutputFile file(c.expected_path);
      {
        std::ofstream out(file.temp_path(), std::ios::binary);
        out << got.dump(2) << "\n";
        if (!out) throw std::runtime_error("cannot write " + c.expected_path.string());
      }
      file.commit();
      std::printf("  updated %-34s %3zu keys, %.2f s\n", c.name.c_str(), got.size(), secs);
      ++passed;
      continue;
    }
    const int m = compare(c.name, c.expected, got);
    if (m == 0) {
      std::printf("  ok   %-34s %3zu keys, %.2f s\n", c.name.c_str(), got.size(), secs);
      ++passed;
    } else {
      std::printf("  FAIL %-34s %d mismatches, %.2f s\n", c.name.c_str(), m, secs);
      ++failed;
    }
  }
  std::printf("regress: %d passed, %d failed\n", passed, failed);
  std::fflush(stdout);
  return failed ? 1 : 0;
}

}  // namespace rtusim
