// The --threads N of every command: a whole number from 1 to 4096, said as such for a word too
// (CLI::Range reads "abc" as a value out of range).
#pragma once
#include <string>

#include <CLI/CLI.hpp>

namespace rtusim {

inline CLI::Validator thread_count() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        const bool digits = !s.empty() && s.size() <= 4 &&
                            s.find_first_not_of("0123456789") == std::string::npos;
        if (digits && std::stoi(s) >= 1 && std::stoi(s) <= 4096) return "";
        return "expected a whole number from 1 to 4096, got '" + s + "'";
      },
      "1..4096");
}

}  // namespace rtusim
