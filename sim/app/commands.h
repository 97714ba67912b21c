// The subcommands of the rtusim executable. Each returns the process exit status and throws
// InputError for bad input (the caller prints it and exits with 2).
#pragma once
#include <string>
#include <vector>

namespace CLI { class App; }

namespace rtusim {

struct RunOptions {
  std::string config;
  std::vector<std::string> overrides;  // --set KEY=VALUE
  std::string out;                     // --out DIR (run) or FILE (hits)
};

struct TraceOptions {
  std::string config;
  std::vector<std::string> overrides;  // --set KEY=VALUE
  std::string out;                     // --out FILE
  std::string format = "din";          // --format din|bin
  std::string level = "l1";            // --level l1 (the node stream) | l2 (the L2's input)
};

struct ReplayOptions {
  std::string trace;                   // a bin or din trace file
  std::vector<std::string> overrides;  // --set l1.*=VALUE
};

struct RegressOptions {
  std::string dir;      // reference cases (default: traces/ beside the project)
  bool update = false;  // --update: rewrite every expected.json (scripts/update_references.sh)
};

struct KeysOptions {
  std::string format = "text";  // --format text|json|markdown (the README's table)
  bool stats = false;           // --stats: the stats keys instead of the config keys
};

int run_command(const RunOptions& opts);
int keys_command(const KeysOptions& opts);
int hits_command(const RunOptions& opts);
int trace_command(const TraceOptions& opts);
int replay_command(const ReplayOptions& opts);
int regress_command(const RegressOptions& opts);
CLI::App* add_sweep_subcommand(CLI::App& app);  // `sweep`: options kept by sweep_command.cpp
int sweep_command();

}  // namespace rtusim
