// The subcommands of the rtusim executable. Each returns the process exit status and throws
// InputError for bad input (the caller prints it and exits with 2).
#pragma once
#include <string>
#include <vector>

namespace rtusim {

struct RunOptions {
  std::string config;
  std::vector<std::string> overrides;  // --set KEY=VALUE
  std::string out;                     // --out DIR (run) or FILE (hits)
};

int run_command(const RunOptions& opts);
int hits_command(const RunOptions& opts);

}  // namespace rtusim
