// Stats keys declared where they are counted, with their kind, unit and description (as config
// keys are declared in config/param.h). Sampling, sweeps, regress and the summary ask a key's
// kind here instead of guessing it from its name; `rtusim keys --stats` lists the declarations.
//
// A declared key may hold placeholders: <stream> (nodes, lists, triangles) and <level> (l1,
// dcache, l2). Forms of a declared key that need no declaration of their own:
//   layout.<kind>.KEY          every layout's value when a run has several layouts
//   units.<i>.KEY              unit i's value on a chip of several units
//   KEY.ci95_low, .ci95_high   the 95% interval of a sampled run's estimate of a counter
//   sample.diff.<a>-<b>.KEY    a sampled run's paired difference of a counter between layouts
#pragma once
#include <string>
#include <vector>

namespace rtusim {

enum class StatKind {
  kCounter,   // counted over the frame's rays: parts of the frame (units, sampled pixels) add up
  kRatio,     // derived from counters (a rate, a fraction, a mean, a maximum): never added up
  kTiming,    // wall-clock time or a rate over it: the only values that differ between runs
  kProperty,  // a fact of the scene, tree, layout or settings, not of the frame's rays
};
const char* stat_kind_name(StatKind k);  // "counter", "ratio", "timing", "property"

struct StatInfo {
  std::string key;  // dotted, maybe with placeholders: "fetch.<stream>.misses"
  StatKind kind;
  std::string unit;  // "bytes", "cycles", "rays", "s", ... or ""
  std::string description;
};

class StatDecl {
 public:
  StatDecl(std::string key, StatKind kind, std::string unit, std::string description);
  StatDecl(const StatDecl&) = delete;
  StatDecl& operator=(const StatDecl&) = delete;
  const StatInfo& info() const { return info_; }

 private:
  StatInfo info_;
};

// Every declaration, in declaration order within a translation unit.
const std::vector<const StatDecl*>& declared_stats();

// The declaration `key` falls under, itself or through one of the forms above; nullptr when
// none does.
const StatInfo* find_stat(const std::string& key);

// A counter itself, or its per-layout or per-unit value (not its interval or a difference):
// what sampling scales from its units to the frame.
bool is_counter_key(const std::string& key);
// A wall-clock key (its per-layout value too): left out where runs are compared.
bool is_timing_key(const std::string& key);

}  // namespace rtusim
