// A config key declared once, next to the code that reads it: key, type, default, range or
// choices, unit and a one-line description. Each declaration is a static object; constructing it
// adds it to declared_params(), which `rtusim keys` and the README key table list. Reading goes
// through the declaration (read()), so the type, default and range checked are the ones listed.
//
//   // in sim/cache/cache_config.cpp
//   const IntParam kAssoc{"l1.assoc", 4, 1, 1 << 24, "ways", "node L1 ways per set"};
//   p.assoc = kAssoc.read(reader);
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/vec3.hpp>

#include "config/config_reader.h"

namespace rtusim {

enum class ParamType { kInt, kFloat, kBool, kString, kStringList, kVec3 };
const char* param_type_name(ParamType t);  // "int", "float", "bool", "string", ...

struct ParamInfo {
  std::string key;           // dotted: "l1.size"
  ParamType type;
  std::string default_text;  // as TOML ("" for an optional key without a default)
  std::string range_text;    // "1..16384", "one of: a, b", or ""
  std::string unit;          // "bytes", "cycles", "ns", ... or ""
  std::string description;
};

// Every declared key, in declaration order within a translation unit.
const std::vector<const class ParamDecl*>& declared_params();

class ParamDecl {
 public:
  ParamDecl(const ParamDecl&) = delete;
  ParamDecl& operator=(const ParamDecl&) = delete;
  const ParamInfo& info() const { return info_; }
  const std::string& key() const { return info_.key; }

 protected:
  explicit ParamDecl(ParamInfo info);

 private:
  ParamInfo info_;
};

// An integer (T = int64_t) or a float (T = double) in [min, max].
template <class T>
class NumberParam final : public ParamDecl {
 public:
  NumberParam(std::string key, T fallback, T min, T max, std::string unit, std::string description);
  T read(ConfigReader& r) const { return read(r, fallback_); }
  // With a default that depends on other keys (a DRAM preset).
  T read(ConfigReader& r, T fallback) const {
    if constexpr (std::is_integral_v<T>)
      return r.get_int(key(), fallback, min_, max_);
    else
      return r.get_float(key(), fallback, min_, max_);
  }

 private:
  T fallback_, min_, max_;
};
using IntParam = NumberParam<int64_t>;
using FloatParam = NumberParam<double>;

// An integer in [min, max], or the word `word` (e.g. l1.assoc = "full"): read() gives nullopt
// for the word, which the effective config keeps as written.
class IntOrWordParam final : public ParamDecl {
 public:
  IntOrWordParam(std::string key, int64_t fallback, int64_t min, int64_t max, std::string word,
                 std::string unit, std::string description);
  std::optional<int64_t> read(ConfigReader& r) const {
    return r.get_int_or_word(key(), fallback_, min_, max_, word_);
  }

 private:
  int64_t fallback_, min_, max_;
  std::string word_;
};

class BoolParam final : public ParamDecl {
 public:
  BoolParam(std::string key, bool fallback, std::string description);
  bool read(ConfigReader& r) const { return r.get_bool(key(), fallback_); }

 private:
  bool fallback_;
};

// A string, one of `choices` when that is not empty.
class StringParam final : public ParamDecl {
 public:
  StringParam(std::string key, std::string fallback, std::vector<std::string> choices,
              std::string unit, std::string description);
  std::string read(ConfigReader& r) const { return r.get_string(key(), fallback_, choices_); }

 private:
  std::string fallback_;
  std::vector<std::string> choices_;
};

// A string or an array of strings, each one of `choices`.
class StringListParam final : public ParamDecl {
 public:
  StringListParam(std::string key, std::vector<std::string> fallback,
                  std::vector<std::string> choices, std::string description);
  std::vector<std::string> read(ConfigReader& r) const {
    return r.get_string_list(key(), fallback_, choices_);
  }

 private:
  std::vector<std::string> fallback_, choices_;
};

// Three numbers; an absent key reads as its default (recorded in the effective config), or as
// nullopt when it has none.
class Vec3Param final : public ParamDecl {
 public:
  Vec3Param(std::string key, std::optional<glm::vec3> fallback, std::string unit,
            std::string description);
  std::optional<glm::vec3> read(ConfigReader& r) const { return r.get_vec3(key(), fallback_); }

 private:
  std::optional<glm::vec3> fallback_;
};

}  // namespace rtusim
