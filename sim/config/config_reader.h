// Reads a TOML run config with `--set` overrides. Every part declares the keys it reads, with
// type, default and range (config/param.h), and reads them through this reader; what it read
// becomes the effective config, and any key nobody read is rejected. Errors name the file, the
// line and the key, or the `--set` the value came from.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <toml++/toml.h>

#include "util/error.h"

namespace rtusim {

// Collects the dotted names of every leaf value of `t` (arrays are leaves), in source order.
void collect_leaves(const toml::table& t, const std::string& prefix,
                    std::vector<std::pair<std::string, const toml::node*>>& out);

// Sets dotted KEY in `root` from one `KEY=VALUE` (VALUE a TOML value, else a bare string),
// making the tables on the way; returns KEY. Throws InputError naming the `--set`.
std::string apply_assignment(toml::table& root, const std::string& assignment);

class ConfigReader {
 public:
  // Parses `path` (throws InputError on a missing file or a TOML syntax error).
  static ConfigReader from_file(const std::string& path);
  // Parses TOML text (`origin` names it in errors).
  static ConfigReader from_string(const std::string& text, const std::string& origin);

  // Applies one `KEY=VALUE` override. VALUE is a TOML value (42, 1.5, true, "s", [1, 2]);
  // anything that does not parse as one is taken as a bare string.
  void apply_override(const std::string& assignment);

  // Typed getters: the value at dotted `key`, or `fallback` when absent. A wrong type or a
  // value out of range throws InputError naming the key and where it was set.
  int64_t get_int(const std::string& key, int64_t fallback, int64_t min, int64_t max);
  // An integer, or the string `word` (nullopt; recorded as the word).
  std::optional<int64_t> get_int_or_word(const std::string& key, int64_t fallback, int64_t min,
                                         int64_t max, const std::string& word);
  double get_float(const std::string& key, double fallback, double min, double max);
  bool get_bool(const std::string& key, bool fallback);
  std::string get_string(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed = {});
  // A string or an array of strings; each must be in `allowed` (if non-empty).
  std::vector<std::string> get_string_list(const std::string& key,
                                           const std::vector<std::string>& fallback,
                                           const std::vector<std::string>& allowed = {});
  // Absent: `fallback`, recorded when there is one.
  std::optional<glm::vec3> get_vec3(const std::string& key, std::optional<glm::vec3> fallback);
  bool has(const std::string& key) const;
  // Where `key`'s value came from, for an error about it: its `--set` assignment, else
  // file:line, else the file (a default).
  std::string where(const std::string& key) const;
  // Where the values of `keys` came from, for an error involving them all: the first one set by
  // `--set`, else the first one in the file, else the file.
  std::string where_first(const std::vector<std::string>& keys) const;

  // Rethrows a params validate() error with where its value came from (where_first of the
  // keys it involves).
  [[noreturn]] void fail(const KeyError& e) const;

  // Throws InputError for the first key (in file order) that no getter asked for; `known`
  // says where the keys that are known are listed.
  void reject_unknown_keys(const std::string& known = "rtusim keys lists them") const;

  // The effective config: every key read, with the value used (defaults included).
  const toml::table& effective() const { return effective_; }
  const std::string& origin() const { return origin_; }
  // Directory of the config file, for resolving relative paths ("" for non-file sources).
  const std::string& base_dir() const { return base_dir_; }

 private:
  const toml::node* find(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  toml::table& effective_table_for(const std::string& key);  // marks `key` read
  template <class V>
  void record(const std::string& key, V&& value) {
    effective_table_for(key).insert_or_assign(key.substr(key.rfind('.') + 1), std::forward<V>(value));
  }

  std::string origin_;
  std::string base_dir_;
  bool from_file_ = false;  // read from a file (not text, as replay's --set)
  toml::table root_;
  std::map<std::string, std::string> override_keys_;  // key -> "--set" text, for errors
  std::map<std::string, bool> used_;
  toml::table effective_;
};

}  // namespace rtusim
