// The --set KEY=VALUE option of every command: one key per --set, repeated for more (a second
// word after one --set is an error, not a second key), shown so in --help.
#pragma once
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace rtusim {

inline CLI::Option* add_set_option(CLI::App* cmd, std::vector<std::string>& sets,
                                   const std::string& what) {
  return cmd->add_option("--set", sets, what + " (one per --set; repeat --set for more)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
}

}  // namespace rtusim
