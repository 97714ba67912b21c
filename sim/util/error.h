// Error kinds shared by every part: bad user input (exit 2) versus internal failure (exit 1).
#pragma once
#include <stdexcept>
#include <string>

namespace rtusim {

// Bad input from the user: a config, scene, trace file or option. The message is one line that
// names the file, the key or line, and what is wrong; the CLI prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace rtusim
