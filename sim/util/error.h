// Error kinds shared by every part: bad user input (exit 2) versus internal failure (exit 1).
#pragma once
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtusim {

// Bad input from the user: a config, scene, trace file or option. The message is one line that
// names the file, the key or line, and what is wrong; the CLI prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// A bad parameter value found by a params validate(): what() is "KEY: DETAIL". `keys` are every
// config key the check involves, the named one first, so the config reader can say where the
// value came from (a `--set`, or the file and line).
class KeyError : public InputError {
 public:
  KeyError(std::initializer_list<std::string> keys_involved, const std::string& detail_text)
      : InputError(*keys_involved.begin() + ": " + detail_text),
        keys(keys_involved),
        detail(detail_text) {}
  KeyError(const std::string& key, const std::string& detail_text) : KeyError({key}, detail_text) {}
  // An InputError from elsewhere whose message already names its keys, with the keys involved.
  KeyError(std::initializer_list<std::string> keys_involved, const InputError& e)
      : InputError(e.what()), keys(keys_involved), detail(e.what()) {}

  std::vector<std::string> keys;
  std::string detail;
};

}  // namespace rtusim
