// Flat dotted-key statistics of a run, written as JSON with keys in sorted order.
#pragma once
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace rtusim {

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
