// The stats declarations' registry and the lookup of a key's declaration.
#include "util/stat_decl.h"

#include <map>
#include <mutex>
#include <regex>
#include <unordered_map>

namespace rtusim {
namespace {

std::vector<const StatDecl*>& registry() {
  static std::vector<const StatDecl*> decls;
  return decls;
}

// A declared key's placeholders, as the words they stand for.
const std::map<std::string, std::string>& placeholders() {
  static const std::map<std::string, std::string> p = {{"<stream>", "(nodes|lists|triangles)"},
                                                       {"<level>", "(l1|dcache|l2)"}};
  return p;
}

// Each declaration as a regular expression of the keys it stands for, made once (after every
// static declaration exists).
const std::vector<std::pair<std::regex, const StatInfo*>>& patterns() {
  static const std::vector<std::pair<std::regex, const StatInfo*>> p = [] {
    std::vector<std::pair<std::regex, const StatInfo*>> out;
    for (const StatDecl* d : registry()) {
      std::string re;
      const std::string& key = d->info().key;
      for (size_t i = 0; i < key.size();) {
        bool placed = false;
        for (const auto& [ph, words] : placeholders())
          if (key.compare(i, ph.size(), ph) == 0) {
            re += words;
            i += ph.size();
            placed = true;
            break;
          }
        if (placed) continue;
        if (key[i] == '.') re += "\\.";
        else re += key[i];
        ++i;
      }
      out.emplace_back(std::regex(re), &d->info());
    }
    return out;
  }();
  return p;
}

// The declaration of `key` itself (no forms), remembered per key: sampling asks for every key
// of every unit it runs.
const StatInfo* find_declared(const std::string& key) {
  static std::mutex mutex;
  static std::unordered_map<std::string, const StatInfo*> known;
  const std::lock_guard<std::mutex> lock(mutex);
  if (const auto it = known.find(key); it != known.end()) return it->second;
  const StatInfo* found = nullptr;
  for (const auto& [re, info] : patterns())
    if (std::regex_match(key, re)) {
      found = info;
      break;
    }
  known.emplace(key, found);
  return found;
}

// `key` without its layout.<kind>. and units.<i>. prefixes (what carries the base key's kind).
std::string without_part_prefix(std::string key) {
  for (const char* prefix : {"layout.", "units."})
    if (key.starts_with(prefix)) {
      const size_t dot = key.find('.', std::string_view(prefix).size());
      if (dot != std::string::npos) key = key.substr(dot + 1);
    }
  return key;
}

}  // namespace

const char* stat_kind_name(StatKind k) {
  switch (k) {
    case StatKind::kCounter: return "counter";
    case StatKind::kRatio: return "ratio";
    case StatKind::kTiming: return "timing";
    case StatKind::kProperty: return "property";
  }
  return "?";
}

StatDecl::StatDecl(std::string key, StatKind kind, std::string unit, std::string description)
    : info_{std::move(key), kind, std::move(unit), std::move(description)} {
  registry().push_back(this);
}

const std::vector<const StatDecl*>& declared_stats() { return registry(); }

const StatInfo* find_stat(const std::string& key) {
  std::string base = without_part_prefix(key);
  if (const StatInfo* info = find_declared(base)) return info;
  // A sampled run's interval bounds and paired differences.
  static const std::regex sampled(R"(^(sample\.diff\.[a-z0-9_-]+-[a-z0-9_-]+\.)?(.*?)(\.ci95_(low|high))?$)");
  std::smatch m;
  if (std::regex_match(base, m, sampled) && (m[1].matched || m[3].matched)) {
    const StatInfo* info = find_declared(m[2].str());
    if (info && info->kind == StatKind::kCounter) return info;
  }
  return nullptr;
}

bool is_counter_key(const std::string& key) {
  const StatInfo* info = find_declared(without_part_prefix(key));
  return info && info->kind == StatKind::kCounter;
}

bool is_timing_key(const std::string& key) {
  const StatInfo* info = find_declared(without_part_prefix(key));
  return info && info->kind == StatKind::kTiming;
}

}  // namespace rtusim
