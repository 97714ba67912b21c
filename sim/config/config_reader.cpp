// TOML config reading with typed, range-checked getters and unknown-key rejection.
#include "config/config_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "util/error.h"
#include "util/read_text_file.h"

namespace rtusim {
namespace {

// Splits "a.b.c" into {"a", "b", "c"}.
std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  return parts;
}

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date/time";
  }
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

}  // namespace

void collect_leaves(const toml::table& t, const std::string& prefix,
                    std::vector<std::pair<std::string, const toml::node*>>& out) {
  for (const auto& [k, v] : t) {
    const std::string name = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = v.as_table()) collect_leaves(*sub, name, out);
    else out.emplace_back(name, &v);
  }
}

ConfigReader ConfigReader::from_string(const std::string& text, const std::string& origin) {
  ConfigReader r;
  r.origin_ = origin;
  try {
    r.root_ = toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    std::string what(e.description());
    std::replace(what.begin(), what.end(), '\n', ' ');
    throw InputError(origin + ":" + std::to_string(e.source().begin.line) + ": " + what);
  }
  return r;
}

ConfigReader ConfigReader::from_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": is a directory, not a config file");
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path + (std::filesystem::exists(path, ec) ? ": not a regular file"
                                                               : ": config file not found"));
  const std::optional<std::string> text = read_text_file(path);
  if (!text) throw InputError(path + ": cannot read config file");
  ConfigReader r = from_string(*text, path);
  r.base_dir_ = std::filesystem::path(path).parent_path().string();
  r.from_file_ = true;
  return r;
}

std::string apply_assignment(toml::table& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set " + assignment + ": expected KEY=VALUE");
  const std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  const auto parts = split_key(key);
  if (parts.empty() || std::any_of(parts.begin(), parts.end(), [](auto& p) { return p.empty(); }))
    throw InputError("--set " + assignment + ": malformed key");
  // Walk/create the tables of the dotted key.
  toml::table* t = &root;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* n = t->get(parts[i]);
    if (!n) n = &t->insert_or_assign(parts[i], toml::table{}).first->second;
    if (!n->as_table())
      throw InputError("--set " + assignment + ": '" + parts[i] + "' is not a table");
    t = n->as_table();
  }
  // The value: a TOML value if it parses as one, else the text as a string.
  try {
    const toml::table parsed = toml::parse("v = " + text);
    parsed.get("v")->visit([&](const auto& v) { t->insert_or_assign(parts.back(), v); });
  } catch (const toml::parse_error&) {
    t->insert_or_assign(parts.back(), text);
  }
  return key;
}

void ConfigReader::apply_override(const std::string& assignment) {
  override_keys_[apply_assignment(root_, assignment)] = "--set " + assignment;
}

const toml::node* ConfigReader::find(const std::string& key) const {
  const toml::table* t = &root_;
  const auto parts = split_key(key);
  for (size_t i = 0; i < parts.size(); ++i) {
    const toml::node* n = t->get(parts[i]);
    if (!n) return nullptr;
    if (i + 1 == parts.size()) return n;
    t = n->as_table();
    if (!t) return nullptr;
  }
  return nullptr;
}

bool ConfigReader::has(const std::string& key) const { return find(key) != nullptr; }

std::string ConfigReader::where(const std::string& key) const {
  if (auto it = override_keys_.find(key); it != override_keys_.end()) return it->second;
  if (const toml::node* n = find(key)) return origin_ + ":" + std::to_string(n->source().begin.line);
  return origin_;
}

void ConfigReader::fail(const std::string& key, const std::string& what) const {
  throw InputError(where(key) + ": " + key + ": " + what);
}

std::string ConfigReader::where_first(const std::vector<std::string>& keys) const {
  for (const std::string& k : keys)
    if (override_keys_.count(k)) return where(k);
  for (const std::string& k : keys)
    if (find(k)) return where(k);
  return origin_;
}

void ConfigReader::fail(const KeyError& e) const {
  throw InputError(where_first(e.keys) + ": " + e.what());
}

toml::table& ConfigReader::effective_table_for(const std::string& key) {
  used_[key] = true;
  const auto parts = split_key(key);
  toml::table* t = &effective_;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* n = t->get(parts[i]);
    if (!n) n = &t->insert_or_assign(parts[i], toml::table{}).first->second;
    t = n->as_table();
  }
  return *t;
}

int64_t ConfigReader::get_int(const std::string& key, int64_t fallback, int64_t min, int64_t max) {
  int64_t v = fallback;
  if (const toml::node* n = find(key)) {
    if (!n->is_integer()) fail(key, "expected an integer, got " + type_name(*n));
    v = n->as_integer()->get();
    if (v < min || v > max)
      fail(key, "must be between " + std::to_string(min) + " and " + std::to_string(max) +
                    ", got " + std::to_string(v));
  }
  record(key, toml::value<int64_t>(v));
  return v;
}

std::optional<int64_t> ConfigReader::get_int_or_word(const std::string& key, int64_t fallback,
                                                     int64_t min, int64_t max,
                                                     const std::string& word) {
  if (const toml::node* n = find(key); n && n->is_string()) {
    if (n->as_string()->get() != word)
      fail(key, "expected an integer or \"" + word + "\", got \"" + n->as_string()->get() + "\"");
    record(key, toml::value<std::string>(word));
    return std::nullopt;
  }
  return get_int(key, fallback, min, max);
}

double ConfigReader::get_float(const std::string& key, double fallback, double min, double max) {
  double v = fallback;
  if (const toml::node* n = find(key)) {
    if (n->is_integer()) v = static_cast<double>(n->as_integer()->get());
    else if (n->is_floating_point()) v = n->as_floating_point()->get();
    else fail(key, "expected a number, got " + type_name(*n));
    if (!(v >= min && v <= max)) {
      std::ostringstream os;
      os << "must be between " << min << " and " << max << ", got " << v;
      fail(key, os.str());
    }
  }
  record(key, toml::value<double>(v));
  return v;
}

bool ConfigReader::get_bool(const std::string& key, bool fallback) {
  bool v = fallback;
  if (const toml::node* n = find(key)) {
    if (!n->is_boolean()) fail(key, "expected true or false, got " + type_name(*n));
    v = n->as_boolean()->get();
  }
  record(key, toml::value<bool>(v));
  return v;
}

std::string ConfigReader::get_string(const std::string& key, const std::string& fallback,
                                     const std::vector<std::string>& allowed) {
  std::string v = fallback;
  if (const toml::node* n = find(key)) {
    if (!n->is_string()) fail(key, "expected a string, got " + type_name(*n));
    v = n->as_string()->get();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end())
      fail(key, "unknown value '" + v + "' (expected one of: " + join(allowed) + ")");
  }
  record(key, toml::value<std::string>(v));
  return v;
}

std::vector<std::string> ConfigReader::get_string_list(const std::string& key,
                                                       const std::vector<std::string>& fallback,
                                                       const std::vector<std::string>& allowed) {
  std::vector<std::string> v = fallback;
  if (const toml::node* n = find(key)) {
    v.clear();
    if (n->is_string()) {
      v.push_back(n->as_string()->get());
    } else if (const toml::array* a = n->as_array()) {
      for (const auto& e : *a) {
        if (!e.is_string()) fail(key, "expected strings in the array, got " + type_name(e));
        v.push_back(e.as_string()->get());
      }
      if (v.empty()) fail(key, "expected at least one value");
    } else {
      fail(key, "expected a string or an array of strings, got " + type_name(*n));
    }
    for (const auto& s : v)
      if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end())
        fail(key, "unknown value '" + s + "' (expected one of: " + join(allowed) + ")");
  }
  toml::array out;
  for (const auto& s : v) out.push_back(s);
  record(key, std::move(out));
  return v;
}

std::optional<glm::vec3> ConfigReader::get_vec3(const std::string& key,
                                                std::optional<glm::vec3> fallback) {
  const toml::node* n = find(key);
  if (!n) {
    used_[key] = true;
    if (fallback) record(key, toml::array{fallback->x, fallback->y, fallback->z});
    return fallback;
  }
  const toml::array* a = n->as_array();
  if (!a || a->size() != 3) fail(key, "expected an array of 3 numbers");
  glm::vec3 v(0.0f);
  for (size_t i = 0; i < 3; ++i) {
    const toml::node& e = *a->get(i);
    if (e.is_integer()) v[int(i)] = static_cast<float>(e.as_integer()->get());
    else if (e.is_floating_point()) v[int(i)] = static_cast<float>(e.as_floating_point()->get());
    else fail(key, "expected an array of 3 numbers, element " + std::to_string(i) + " is " + type_name(e));
    if (!std::isfinite(v[int(i)])) fail(key, "expected finite numbers");
  }
  record(key, toml::array{v.x, v.y, v.z});
  return v;
}

void ConfigReader::reject_unknown_keys(const std::string& known) const {
  std::vector<std::pair<std::string, const toml::node*>> leaves;
  collect_leaves(root_, "", leaves);
  for (const auto& [name, node] : leaves) {
    if (used_.count(name)) continue;
    if (name.starts_with("sweep.") && from_file_ && !override_keys_.count(name))
      fail(name, "a [sweep] table belongs in a sweep spec: run this file with `rtusim sweep`");
    fail(name, "unknown key (" + known + ")");
  }
}

}  // namespace rtusim
