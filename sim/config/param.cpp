// The key registry and the typed declarations.
#include "config/param.h"

#include <cstdint>
#include <limits>
#include <sstream>

namespace rtusim {
namespace {

std::vector<const ParamDecl*>& registry() {
  static std::vector<const ParamDecl*> params;
  return params;
}

template <class T>
std::string number_text(T v) {
  std::ostringstream os;
  os << v;
  std::string s = os.str();
  if constexpr (std::is_floating_point_v<T>)
    if (s.find_first_of(".e") == std::string::npos && s.find("inf") == std::string::npos) s += ".0";
  return s;
}

template <class T>
std::string range_text(T min, T max) {
  if (max == std::numeric_limits<T>::max()) return ">= " + number_text(min);
  return number_text(min) + ".." + number_text(max);
}

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

std::string vec3_text(const glm::vec3& v) {
  std::string t = "[";
  for (int i = 0; i < 3; ++i) t.append(i ? ", " : "").append(number_text(double(v[i])));
  return t.append("]");
}

std::string choices_text(const std::vector<std::string>& choices) {
  if (choices.empty()) return "";
  std::string t = "one of: ";
  for (size_t i = 0; i < choices.size(); ++i) t += (i ? ", " : "") + choices[i];
  return t;
}

}  // namespace

const char* param_type_name(ParamType t) {
  switch (t) {
    case ParamType::kInt: return "int";
    case ParamType::kFloat: return "float";
    case ParamType::kBool: return "bool";
    case ParamType::kString: return "string";
    case ParamType::kStringList: return "string list";
    case ParamType::kVec3: return "float[3]";
  }
  return "?";
}

const std::vector<const ParamDecl*>& declared_params() { return registry(); }

ParamDecl::ParamDecl(ParamInfo info) : info_(std::move(info)) { registry().push_back(this); }

template <class T>
NumberParam<T>::NumberParam(std::string key, T fallback, T min, T max, std::string unit,
                            std::string description)
    : ParamDecl({std::move(key), std::is_integral_v<T> ? ParamType::kInt : ParamType::kFloat,
                 number_text(fallback), range_text(min, max), std::move(unit),
                 std::move(description)}),
      fallback_(fallback), min_(min), max_(max) {}

template class NumberParam<int64_t>;
template class NumberParam<double>;

IntOrWordParam::IntOrWordParam(std::string key, int64_t fallback, int64_t min, int64_t max,
                               std::string word, std::string unit, std::string description)
    : ParamDecl({std::move(key), ParamType::kInt, number_text(fallback),
                 range_text(min, max) + " or " + quoted(word), std::move(unit),
                 std::move(description)}),
      fallback_(fallback), min_(min), max_(max), word_(std::move(word)) {}

BoolParam::BoolParam(std::string key, bool fallback, std::string description)
    : ParamDecl({std::move(key), ParamType::kBool, fallback ? "true" : "false", "", "",
                 std::move(description)}),
      fallback_(fallback) {}

StringParam::StringParam(std::string key, std::string fallback, std::vector<std::string> choices,
                         std::string unit, std::string description)
    : ParamDecl({std::move(key), ParamType::kString, quoted(fallback), choices_text(choices),
                 std::move(unit), std::move(description)}),
      fallback_(std::move(fallback)), choices_(std::move(choices)) {}

StringListParam::StringListParam(std::string key, std::vector<std::string> fallback,
                                 std::vector<std::string> choices, std::string description)
    : ParamDecl({std::move(key), ParamType::kStringList,
                 [&] {
                   std::string t = "[";
                   for (size_t i = 0; i < fallback.size(); ++i)
                     t += (i ? ", " : "") + quoted(fallback[i]);
                   return t + "]";
                 }(),
                 choices_text(choices), "", std::move(description)}),
      fallback_(std::move(fallback)), choices_(std::move(choices)) {}

Vec3Param::Vec3Param(std::string key, std::optional<glm::vec3> fallback, std::string unit,
                     std::string description)
    : ParamDecl({std::move(key), ParamType::kVec3, fallback ? vec3_text(*fallback) : "", "",
                 std::move(unit), std::move(description)}),
      fallback_(fallback) {}

}  // namespace rtusim
