// `rtusim keys`: every declared config key (config/param.h) with type, default, range, unit and
// description; text, json, or the README's markdown table.
#include <algorithm>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "app/commands.h"
#include "config/param.h"
#include "util/error.h"
#include "util/stat_decl.h"

namespace rtusim {
namespace {

// Keys grouped by subtree in config-file order, alphabetical within a subtree.
std::vector<const ParamInfo*> sorted_keys() {
  static const std::vector<std::string> kSections = {
      "scene", "camera", "image", "tracer", "kdtree", "layout", "l1",
      "dcache", "chip", "l2", "sim", "isect", "dram", "sample", "report"};
  auto rank = [](const std::string& key) {
    const std::string section = key.substr(0, key.find('.'));
    const auto it = std::find(kSections.begin(), kSections.end(), section);
    return static_cast<size_t>(it - kSections.begin());
  };
  std::vector<const ParamInfo*> keys;
  for (const ParamDecl* d : declared_params()) keys.push_back(&d->info());
  std::sort(keys.begin(), keys.end(), [&](const ParamInfo* a, const ParamInfo* b) {
    const size_t ra = rank(a->key), rb = rank(b->key);
    return ra != rb ? ra < rb : a->key < b->key;
  });
  return keys;
}

// A TOML value as JSON (a key's default, kept as TOML text): null when there is none.
nlohmann::ordered_json json_value(const toml::node& n) {
  if (const auto* a = n.as_array()) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const toml::node& e : *a) out.push_back(json_value(e));
    return out;
  }
  if (const auto* v = n.as_string()) return v->get();
  if (const auto* v = n.as_integer()) return v->get();
  if (const auto* v = n.as_floating_point()) return v->get();
  if (const auto* v = n.as_boolean()) return v->get();
  return nullptr;
}
nlohmann::ordered_json json_default(const std::string& toml_text) {
  if (toml_text.empty()) return nullptr;
  try {
    const toml::table t = toml::parse("v = " + toml_text);
    return json_value(*t.get("v"));
  } catch (const toml::parse_error&) {
    return toml_text;
  }
}

std::string markdown_cell(std::string s) {
  for (size_t i = 0; (i = s.find('|', i)) != std::string::npos; i += 2) s.replace(i, 1, "\\|");
  return s;
}

// The stats keys in declaration order sorted by key.
std::vector<const StatInfo*> sorted_stats() {
  std::vector<const StatInfo*> stats;
  for (const StatDecl* d : declared_stats()) stats.push_back(&d->info());
  std::sort(stats.begin(), stats.end(),
            [](const StatInfo* a, const StatInfo* b) { return a->key < b->key; });
  return stats;
}

// The forms of a declared key that stats.json may hold (util/stat_decl.h).
const char* const kStatForms[][2] = {
    {"layout.<kind>.KEY", "every layout's value when a run has several layouts"},
    {"units.<i>.KEY", "unit i's value on a chip of several units (or with an L2)"},
    {"KEY.ci95_low, KEY.ci95_high", "the 95% interval of a sampled run's estimate of a counter"},
    {"sample.diff.<a>-<b>.KEY", "a sampled run's paired difference of a counter, layout a - b"},
};

int stats_keys(const std::string& format) {
  const std::vector<const StatInfo*> stats = sorted_stats();
  if (format == "json") {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const StatInfo* k : stats)
      out.push_back({{"key", k->key}, {"kind", stat_kind_name(k->kind)}, {"unit", k->unit},
                     {"description", k->description}});
    std::cout << out.dump(2) << "\n";
  } else if (format == "markdown") {
    std::cout << "| key | kind | unit | description |\n|---|---|---|---|\n";
    for (const StatInfo* k : stats)
      std::cout << "| `" << k->key << "` | " << stat_kind_name(k->kind) << " | " << k->unit
                << " | " << markdown_cell(k->description) << " |\n";
    std::cout << "\nForms of a key KEY above: ";
    for (size_t i = 0; i < std::size(kStatForms); ++i)
      std::cout << (i ? "; " : "") << '`' << kStatForms[i][0] << "`: " << kStatForms[i][1];
    std::cout << ". `<stream>` is nodes, lists or triangles; `<level>` l1, dcache or l2.\n";
  } else if (format == "text") {
    for (const StatInfo* k : stats) {
      std::printf("%-34s %-8s %s\n", k->key.c_str(), stat_kind_name(k->kind), k->unit.c_str());
      std::printf("%36s%s\n", "", k->description.c_str());
    }
    std::printf("\nforms of a key KEY above:\n");
    for (const auto& form : kStatForms) std::printf("  %-32s %s\n", form[0], form[1]);
  } else {
    throw InputError("keys --format " + format + ": expected text, json or markdown");
  }
  return 0;
}

}  // namespace

int keys_command(const KeysOptions& opts) {
  if (opts.stats) return stats_keys(opts.format);
  const std::vector<const ParamInfo*> keys = sorted_keys();
  if (opts.format == "json") {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const ParamInfo* k : keys)
      out.push_back({{"key", k->key}, {"type", param_type_name(k->type)},
                     {"default", json_default(k->default_text)}, {"range", k->range_text},
                     {"unit", k->unit}, {"description", k->description}});
    std::cout << out.dump(2) << "\n";
  } else if (opts.format == "markdown") {
    std::cout << "| key | type | default | range | unit | description |\n"
              << "|---|---|---|---|---|---|\n";
    for (const ParamInfo* k : keys) {
      std::cout << "| `" << k->key << "` | " << param_type_name(k->type) << " | ";
      if (!k->default_text.empty()) std::cout << '`' << markdown_cell(k->default_text) << '`';
      std::cout << " | " << markdown_cell(k->range_text) << " | " << k->unit << " | "
                << markdown_cell(k->description) << " |\n";
    }
  } else if (opts.format == "text") {
    for (const ParamInfo* k : keys) {
      std::printf("%-26s %-11s %s", k->key.c_str(), param_type_name(k->type),
                  k->default_text.empty() ? "(none)" : k->default_text.c_str());
      if (!k->range_text.empty()) std::printf("  [%s]", k->range_text.c_str());
      if (!k->unit.empty()) std::printf("  %s", k->unit.c_str());
      std::printf("\n%28s%s\n", "", k->description.c_str());
    }
  } else {
    throw InputError("keys --format " + opts.format + ": expected text, json or markdown");
  }
  return 0;
}

}  // namespace rtusim
