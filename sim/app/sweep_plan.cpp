#include "app/sweep_plan.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "app/pipeline.h"
#include "app/run_config.h"
#include "config/config_reader.h"
#include "tier/functional_tier.h"
#include "util/error.h"
#include "util/read_text_file.h"

namespace rtusim {
namespace {

namespace fs = std::filesystem;

// One dimension of the product: a key with its values, or a group of keys set together.
struct Dim {
  std::string name;                         // the key, or "group.NAME"
  std::vector<std::string> keys;            // config keys it sets
  std::vector<std::vector<std::string>> values;  // [entry][key]: TOML text, "" = not set
  std::vector<std::vector<std::string>> cells;   // [entry][key]: CSV text
  std::vector<uint32_t> lines;                   // [entry]: its line in the spec
};

// Keys whose values only change the caches or the layout: points differing in them share a job.
bool is_cache_key(const std::string& key) {
  static const std::set<std::string> keys = {
      "l1.size",     "l1.assoc",     "l1.line",     "l1.policy",     "l1.seed",
      "dcache.enable", "dcache.size", "dcache.assoc", "dcache.line", "dcache.policy",
      "dcache.seed", "layout.kind"};
  return keys.count(key) != 0;
}

// Keys whose values only change a chip's LRU L2 (or the layout): chip points differing in them
// share an L2 job.
bool is_l2_family_key(const std::string& key) {
  return key == "l2.size" || key == "l2.assoc" || key == "layout.kind";
}

// Inner dimensions in this order (the rest by name): layout, then per cache policy, line,
// associativity, size (the size varies fastest: a row block is a miss-ratio curve).
int inner_rank(const std::string& key) {
  static const std::vector<std::string> order = {
      "layout.kind",   "l1.policy",   "l1.line",      "l1.assoc",   "l1.size",
      "dcache.policy", "dcache.line", "dcache.assoc", "dcache.size"};
  const auto it = std::find(order.begin(), order.end(), key);
  return static_cast<int>(it - order.begin());
}

std::string value_text(const toml::node& v) {
  toml::table one;
  one.insert("v", v);
  std::ostringstream os;
  os << one;
  return os.str().substr(4);  // after "v = "
}

std::string cell_text(const toml::node& v) {
  if (const auto* s = v.as_string()) return s->get();
  return value_text(v);
}

std::string type_name(const toml::node& n) {
  if (n.is_table()) return "a table";
  if (n.is_array()) return "an array";
  return "a single value";
}

// A relative scene path becomes absolute against the spec's directory (the base config and the
// runs live in the output directory).
std::string absolute_scene_path(const std::string& path, const fs::path& spec_dir) {
  if (path.rfind("builtin:", 0) == 0 || path.rfind("$RTUSIM_SCENES", 0) == 0 ||
      path.rfind("${RTUSIM_SCENES}", 0) == 0 || fs::path(path).is_absolute())
    return path;
  return fs::absolute(spec_dir / path).lexically_normal().string();
}

// "key = cell, ..." of the keys a point or entry sets.
std::string describe(const std::vector<std::string>& keys, const std::vector<std::string>& cells) {
  std::string s;
  for (size_t i = 0; i < keys.size(); ++i)
    if (!cells[i].empty()) s += (s.empty() ? "" : ", ") + keys[i] + " = " + cells[i];
  return s;
}

// The [sweep] table as dimensions.
std::vector<Dim> read_dims(const toml::table& sweep, const std::string& spec,
                           const fs::path& spec_dir) {
  std::vector<Dim> dims;
  const auto at = [&](uint32_t line) { return spec + ":" + std::to_string(line); };
  const auto set_text = [&](const std::string& key, const toml::node& v) {
    if (key == "scene.path" && v.is_string())
      return value_text(
          toml::value<std::string>(absolute_scene_path(v.as_string()->get(), spec_dir)));
    if (const auto* i = v.as_integer())  // 0x2000 and 8192 are one value
      return value_text(toml::value<int64_t>(i->get()));
    return value_text(v);
  };
  std::vector<std::pair<std::string, const toml::node*>> keys;
  for (const auto& [k, v] : sweep) {
    if (k.str() != "group") {
      if (const auto* t = v.as_table()) collect_leaves(*t, std::string(k.str()), keys);
      else keys.emplace_back(std::string(k.str()), &v);
      continue;
    }
    const auto* groups = v.as_table();
    if (!groups) throw InputError(spec + ": [sweep] group: expected [[sweep.group.NAME]] tables");
    for (const auto& [name, entries] : *groups) {
      const std::string where = spec + ": [sweep.group." + std::string(name.str()) + "]";
      const auto* arr = entries.as_array();
      if (!arr || !arr->is_array_of_tables())
        throw InputError(at(entries.source().begin.line) + ": [sweep.group." +
                         std::string(name.str()) + "]: expected [[sweep.group." +
                         std::string(name.str()) + "]] entries (tables of keys set together)");
      if (arr->empty()) throw InputError(where + ": empty group");
      Dim d;
      d.name = "group." + std::string(name.str());
      std::vector<std::vector<std::pair<std::string, const toml::node*>>> per_entry;
      std::set<std::string> all;
      for (const auto& e : *arr) {
        d.lines.push_back(e.source().begin.line);
        per_entry.emplace_back();
        collect_leaves(*e.as_table(), "", per_entry.back());
        if (per_entry.back().empty()) throw InputError(where + ": an entry sets no key");
        for (const auto& [key, node] : per_entry.back()) all.insert(key);
      }
      d.keys.assign(all.begin(), all.end());
      for (const auto& entry : per_entry) {
        std::vector<std::string> vals(d.keys.size()), cells(d.keys.size());
        for (const auto& [key, node] : entry) {
          const size_t i = std::find(d.keys.begin(), d.keys.end(), key) - d.keys.begin();
          vals[i] = set_text(key, *node);
          cells[i] = cell_text(*node);
        }
        d.values.push_back(vals);
        d.cells.push_back(cells);
      }
      dims.push_back(std::move(d));
    }
  }
  for (const auto& [key, node] : keys) {
    const auto* arr = node->as_array();
    if (!arr)
      throw InputError(at(node->source().begin.line) + ": [sweep] " + key + " = " +
                       value_text(*node) + ": expected a list of values, got " + type_name(*node));
    if (arr->empty())
      throw InputError(at(node->source().begin.line) + ": [sweep] " + key +
                       ": empty list of values");
    Dim d;
    d.name = key;
    d.keys = {key};
    for (const auto& v : *arr) {
      d.lines.push_back(v.source().begin.line);
      d.values.push_back({set_text(key, v)});
      d.cells.push_back({cell_text(v)});
    }
    dims.push_back(std::move(d));
  }
  // Each key in one dimension, each value (or group entry) once: a point is one combination.
  const auto table = [](const Dim& d) {
    return d.name.rfind("group.", 0) == 0 ? "[sweep." + d.name + "]" : std::string("[sweep]");
  };
  const auto label = [&](const Dim& d) {
    return d.name.rfind("group.", 0) == 0 ? table(d) : "[sweep] " + d.name;
  };
  std::map<std::string, const Dim*> owner;
  for (const Dim& d : dims) {
    for (const auto& k : d.keys)
      if (const auto [it, fresh] = owner.try_emplace(k, &d); !fresh)
        throw InputError(at(d.lines.front()) + ": " + table(d) + " " + k + ": also swept by " +
                         table(*it->second));
    for (size_t e = 0; e < d.values.size(); ++e)
      for (size_t f = 0; f < e; ++f)
        if (d.values[e] == d.values[f])
          throw InputError(at(d.lines[e]) + ": " + label(d) + ": " +
                           (d.keys.size() == 1 ? "value " + d.cells[e][0]
                                               : "entry " + std::to_string(e + 1) + " (" +
                                                     describe(d.keys, d.cells[e]) + ")") +
                           " is listed twice");
  }
  return dims;
}

// The base config in a temporary file, for validating points before the output directory exists.
class TempFile {
 public:
  explicit TempFile(const std::string& text)
      : path_(fs::temp_directory_path() /
              ("rtusim-sweep-" + std::to_string(::getpid()) + "-base.toml")) {
    std::ofstream(path_) << text;
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  std::string path() const { return path_.string(); }

 private:
  fs::path path_;
};

// The message of a config error with the temporary base file's name (and line) cut off.
std::string inner_message(const std::string& what, const std::string& base_path,
                          const std::vector<std::string>& user_sets) {
  for (const std::string& set : user_sets)  // the user's own --set is named as such
    if (what.rfind("--set " + set + ": ", 0) == 0) return what;
  if (what.rfind("--set ", 0) == 0 && what.find(": ") != std::string::npos)
    return what.substr(what.find(": ") + 2);  // a point's key: the sweep names key and value
  if (what.rfind(base_path, 0) != 0) return what;
  size_t i = base_path.size();
  if (i < what.size() && what[i] == ':') ++i;
  while (i < what.size() && (std::isdigit(static_cast<unsigned char>(what[i])) || what[i] == ':'))
    ++i;
  while (i < what.size() && what[i] == ' ') ++i;
  return what.substr(i);
}

}  // namespace

SweepPlan plan_sweep(const std::string& spec_path, const std::vector<std::string>& user_sets,
                     bool check_scenes) {
  SweepPlan plan;
  plan.spec_path = spec_path;
  {
    std::error_code ec;
    if (!fs::is_regular_file(spec_path, ec)) throw InputError(spec_path + ": sweep spec not found");
    std::optional<std::string> text = read_text_file(spec_path);
    if (!text) throw InputError(spec_path + ": cannot read sweep spec");
    plan.spec_text = std::move(*text);
  }
  toml::table root;
  try {
    root = toml::parse(plan.spec_text, spec_path);
  } catch (const toml::parse_error& e) {
    std::string what(e.description());
    std::replace(what.begin(), what.end(), '\n', ' ');
    throw InputError(spec_path + ":" + std::to_string(e.source().begin.line) + ": " + what);
  }
  const auto* sweep = root["sweep"].as_table();
  if (!sweep)
    throw InputError(spec_path + ": [sweep]: missing (a sweep spec is a run config plus a "
                     "[sweep] table of keys with lists of values)");
  const fs::path spec_dir = fs::absolute(fs::path(spec_path)).parent_path();
  // The command's --set; a relative scene path among them made absolute against the spec's
  // directory, as `rtusim run SPEC --set scene.path=…` reads it (the runs live elsewhere).
  std::vector<std::string> sets = user_sets;
  for (std::string& set : sets)
    if (set.rfind("scene.path=", 0) == 0) {
      toml::table t;
      apply_assignment(t, set);
      if (const auto* path = t["scene"]["path"].as_string())
        set = "scene.path=" +
              value_text(toml::value<std::string>(absolute_scene_path(path->get(), spec_dir)));
    }
  plan.sets = sets;
  std::vector<Dim> dims = read_dims(*sweep, spec_path, spec_dir);
  for (const std::string& set : sets) {
    const std::string key = set.substr(0, set.find('='));
    const auto overlaps = [&](const std::string& swept) {  // the key, or a table around it
      return swept == key || swept.rfind(key + ".", 0) == 0 || key.rfind(swept + ".", 0) == 0;
    };
    for (const Dim& d : dims)
      if (const auto k = std::find_if(d.keys.begin(), d.keys.end(), overlaps); k != d.keys.end())
        throw InputError("--set " + set + ": " + *k + " is swept by " + spec_path +
                         " ([sweep" + (d.name.rfind("group.", 0) == 0 ? "." + d.name : "") +
                         "]); each point's value would replace it");
  }

  // The base config: the spec without [sweep], with the command's --set.
  toml::table base = root;
  base.erase("sweep");
  for (const std::string& set : sets) apply_assignment(base, set);
  if (auto* path = base["scene"]["path"].as_string())
    *path = absolute_scene_path(path->get(), spec_dir);
  std::ostringstream os;
  os << base;
  plan.base_toml = "# The base config of the sweep " + spec_path +
                   " (its [sweep] table removed, the --set applied)\n" + os.str() + "\n";
  const TempFile base_file(plan.base_toml);

  // Loads a config of the sweep (the base with `overrides`); its errors are the config's, which
  // located() places in the spec: at the line of a value or entry, or as a point or the base.
  const auto load_config = [&](const std::vector<std::string>& overrides) {
    RunConfig c = load_run_config(base_file.path(), overrides);
    if (c.scene.resolved.rfind("builtin:", 0) != 0 && !fs::exists(c.scene.resolved))
      throw InputError("scene.path: " + c.scene.resolved + " not found");
    return c;
  };
  const auto located = [&](const std::string& what, uint32_t line, const std::string& inner) {
    return InputError(spec_path + (line ? ":" + std::to_string(line) : "") + ": " + what + ": " +
                      inner);
  };
  // The base config's load, its errors placed as `what`.
  const auto load = [&](const std::vector<std::string>& overrides, const std::string& what,
                        uint32_t line = 0) {
    try {
      return load_config(overrides);
    } catch (const InputError& e) {
      throw located(what, line, inner_message(e.what(), base_file.path(), sets));
    }
  };
  const RunConfig base_config = load(sets, "base config");

  // Several layouts in the base config and none swept: each is a point of its own.
  const bool layout_swept = std::any_of(dims.begin(), dims.end(), [](const Dim& d) {
    return std::count(d.keys.begin(), d.keys.end(), "layout.kind") != 0;
  });
  if (!layout_swept && base_config.layout.kinds.size() > 1) {
    Dim d{"layout.kind", {"layout.kind"}, {}, {}, {}};
    for (const auto& k : base_config.layout.kinds) {
      d.values.push_back({"'" + k + "'"});
      d.cells.push_back({k});
      d.lines.push_back(0);  // from the base config, not a line of [sweep]
    }
    dims.push_back(std::move(d));
  }

  // Outer dimensions (they change the traced frame) by name, then the cache dimensions.
  const auto inner = [](const Dim& d) {
    return std::all_of(d.keys.begin(), d.keys.end(), is_cache_key);
  };
  std::stable_sort(dims.begin(), dims.end(), [&](const Dim& a, const Dim& b) {
    if (inner(a) != inner(b)) return !inner(a);
    if (inner(a)) {
      const int ra = inner_rank(a.name), rb = inner_rank(b.name);
      if (ra != rb) return ra < rb;
    }
    return a.name < b.name;
  });
  for (const Dim& d : dims)
    for (const auto& k : d.keys) plan.columns.push_back(k);

  // Every value alone on the base config: its error, if any ("" if none). A value may fail
  // alone and hold with the other swept values (l1.assoc = 3 with l1.size = [3072, 6144]), so
  // an error stops the sweep only when a point meets it: then named at the value's line.
  std::vector<std::vector<std::string>> alone_error(dims.size());
  const auto value_what = [](const Dim& d, size_t e) {
    return d.name.rfind("group.", 0) == 0 ? "[sweep." + d.name + "] " + describe(d.keys, d.cells[e])
                                          : "[sweep] " + d.keys[0] + " = " + d.cells[e][0];
  };
  for (size_t i = 0; i < dims.size(); ++i) {
    const Dim& d = dims[i];
    for (size_t e = 0; e < d.values.size(); ++e) {
      std::vector<std::string> o = sets;
      for (size_t k = 0; k < d.keys.size(); ++k)
        if (!d.values[e][k].empty()) o.push_back(d.keys[k] + "=" + d.values[e][k]);
      std::string error;
      try {
        load_config(o);
      } catch (const InputError& ex) {
        error = inner_message(ex.what(), base_file.path(), sets);
      }
      alone_error[i].push_back(error);
    }
  }

  // The product; each point validated as a whole.
  size_t total = 1;
  for (const Dim& d : dims) total *= d.values.size();
  std::map<std::string, size_t> job_of_key;
  std::set<std::string> checked_cameras;
  std::map<std::string, Scene> scenes;  // by resolved path
  for (size_t index = 0; index < total; ++index) {
    SweepPoint pt;
    std::vector<size_t> entry(dims.size());
    for (size_t i = dims.size(), rest = index; i-- > 0;) {
      entry[i] = rest % dims[i].values.size();
      rest /= dims[i].values.size();
    }
    std::string job_key, l2_job_key = "l2\n";
    for (size_t i = 0; i < dims.size(); ++i)
      for (size_t k = 0; k < dims[i].keys.size(); ++k) {
        const std::string& v = dims[i].values[entry[i]][k];
        // A relative scene path as the point reads it (against the spec's directory), so the
        // cell reruns the point from anywhere.
        const std::string& cell = dims[i].cells[entry[i]][k];
        pt.cells.push_back(dims[i].keys[k] == "scene.path" && !v.empty()
                               ? absolute_scene_path(cell, spec_dir)
                               : cell);
        if (v.empty()) continue;
        pt.overrides.push_back(dims[i].keys[k] + "=" + v);
        if (!is_cache_key(dims[i].keys[k])) job_key += pt.overrides.back() + "\n";
        if (!is_l2_family_key(dims[i].keys[k])) l2_job_key += pt.overrides.back() + "\n";
      }
    std::vector<std::string> all = sets;
    all.insert(all.end(), pt.overrides.begin(), pt.overrides.end());
    // An error of this point, named by the swept value or entry whose own error it is; else,
    // `by_key` (an error that only the whole point shows, about one key: its scene, camera or
    // layout), by the value or entry that sets that key, or the base config when none does;
    // else as the point (a combination of its values).
    const auto point_error = [&](const std::string& error, bool by_key) {
      for (size_t i = 0; i < dims.size(); ++i)
        if (alone_error[i][entry[i]] == error)
          return located(value_what(dims[i], entry[i]), dims[i].lines[entry[i]], error);
      const std::string point =
          "[sweep] point " + std::to_string(index) + " (" + describe(plan.columns, pt.cells) + ")";
      if (!by_key) return located(point, 0, error);
      const std::string key = error.substr(0, error.find(": "));
      for (size_t i = 0; i < dims.size(); ++i)
        for (size_t k = 0; k < dims[i].keys.size(); ++k)
          if (dims[i].keys[k] == key && !dims[i].values[entry[i]][k].empty())
            return located(value_what(dims[i], entry[i]), dims[i].lines[entry[i]], error);
      return located(point + ", from the base config", 0, error);
    };
    std::optional<RunConfig> loaded;
    try {
      loaded = load_config(all);
    } catch (const InputError& ex) {
      throw point_error(inner_message(ex.what(), base_file.path(), sets), false);
    }
    const RunConfig& c = *loaded;
    // The scene and camera, which only loading the scene checks, so that a scene that does not
    // load stops the sweep before anything runs: each scene loaded once, each camera checked
    // once (not again in the runners' jobs, which plan with check_scenes false).
    if (check_scenes) {
      std::ostringstream camera_key;
      camera_key << std::hexfloat << c.scene.resolved << '\n' << c.scene.camera << '\n'
                 << c.scene_vfov_deg.value_or(0.0f);
      if (c.camera) {
        for (const glm::vec3& v : {c.camera->eye, c.camera->target, c.camera->up})
          camera_key << ' ' << v.x << ' ' << v.y << ' ' << v.z;
        camera_key << ' ' << c.camera->vfov_deg;
      }
      if (checked_cameras.insert(camera_key.str()).second) {
        try {
          auto it = scenes.find(c.scene.resolved);
          if (it == scenes.end()) it = scenes.emplace(c.scene.resolved, load_config_scene(c)).first;
          checked_camera(c, it->second);
        } catch (const InputError& ex) {
          throw point_error(inner_message(ex.what(), base_file.path(), sets), true);
        }
      }
    }
    if (c.layout.kinds.size() != 1)
      throw point_error("layout.kind: a point has one layout (sweep layout.kind instead)", true);
    pt.caches = c.fetch_caches();
    pt.layout = c.layout.kinds.front();
    pt.chip = c.chip;
    const bool plain = c.sim.tier == FunctionalTier::kName && !c.sample.active() &&
                       !c.functional.interleaved();
    const bool l2_family = plain && c.chip.l2 && c.chip.l2->policy == "lru";
    pt.alone = !plain || (!c.chip.single_unit() && !l2_family);
    if (pt.alone) {
      pt.job = plan.jobs.size();
      plan.jobs.push_back(SweepJob{{index}, true});
    } else {
      auto [it, fresh] =
          job_of_key.try_emplace(l2_family ? l2_job_key : job_key, plan.jobs.size());
      if (fresh) plan.jobs.push_back(SweepJob{{}, false, l2_family});
      pt.job = it->second;
      plan.jobs[pt.job].points.push_back(index);
    }
    plan.points.push_back(std::move(pt));
  }
  return plan;
}

std::string job_error(const SweepPlan& plan, size_t job, const std::string& base_path,
                      const std::string& what) {
  const SweepJob& j = plan.jobs.at(job);
  const SweepPoint& pt = plan.points.at(j.points.front());
  std::vector<std::string> keys, cells;
  for (size_t i = 0; i < plan.columns.size(); ++i)
    if (j.alone || (j.l2_family ? !is_l2_family_key(plan.columns[i])
                                : !is_cache_key(plan.columns[i]))) {
      keys.push_back(plan.columns[i]);
      cells.push_back(pt.cells[i]);
    }
  const std::string set = describe(keys, cells);
  return plan.spec_path + ": [sweep] job " + std::to_string(job) +
         (set.empty() ? "" : " (" + set + ")") + ": " + inner_message(what, base_path, plan.sets);
}

}  // namespace rtusim
