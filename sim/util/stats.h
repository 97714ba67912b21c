// Flat dotted-key statistics of a run, written as JSON with keys in sorted order.
#pragma once
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace rtusim {

// A key whose value is wall-clock time or a rate over it (`*seconds`, `trace.rays_per_second`,
// `sample.rays_simulated_per_second`, also under a `layout.<kind>.` prefix): the only keys that
// differ between runs of one config. Rates over simulated time (`sim.rays_per_second`,
// `dram.gbytes_per_second`, `report.*_per_second`) are results.
inline bool is_timing_key(const std::string& key) {
  return key.ends_with("seconds") || key.ends_with("trace.rays_per_second") ||
         key.ends_with("sample.rays_simulated_per_second");
}

class Stats {
 public:
  template <class T>
  void set(const std::string& key, const T& value) {
    values_[key] = value;
  }
  const nlohmann::json& at(const std::string& key) const { return values_.at(key); }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  const std::map<std::string, nlohmann::json>& values() const { return values_; }
  nlohmann::json to_json() const {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [k, v] : values_) j[k] = v;
    return j;
  }

 private:
  std::map<std::string, nlohmann::json> values_;
};

}  // namespace rtusim
