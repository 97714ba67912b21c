// libFuzzer target: the TOML config reader and --set overrides. The input is a config text;
// each line after a line "--set" is one override. Any InputError is a clean rejection.
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "config/config_reader.h"
#include "app/run_config.h"
#include "fuzz_util.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace rtusim;
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  if (const size_t cut = text.find("\n--set\n"); cut != std::string::npos) {
    std::istringstream rest(text.substr(cut + 7));
    for (std::string line; std::getline(rest, line);) overrides.push_back(line);
    text.resize(cut);
  }
  try {
    ConfigReader r = ConfigReader::from_string(text, "fuzz.toml");
    for (const auto& o : overrides) r.apply_override(o);
  } catch (const InputError&) {
  }
  // The whole run config (validation included), from a file as the CLI reads it.
  const auto path = fuzz::write_file("fuzz.toml", reinterpret_cast<const uint8_t*>(text.data()),
                                     text.size());
  try {
    load_run_config(path.string(), overrides);
  } catch (const InputError&) {
  }
  return 0;
}
