// One registry per seam (layouts, replacement policies, DRAM backends, tiers): the list of the
// seam's implementation types, each with `static constexpr const char* kName`. The list is the
// registration: a new implementation is its own file plus one entry in its seam's list.
//
// Dispatch is static: dispatch(name, f) calls f.template operator()<T>() with the concrete type
// named, so a hot loop inside f is compiled once per implementation with its calls inlined (no
// virtual call per fetch); variant_of<W> is a std::variant over W<T> for every T (then W<Extra>...).
#pragma once
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace rtusim {

template <class... Ts>
struct TypeRegistry {
  static_assert(sizeof...(Ts) > 0);

  // Names in list order.
  static std::vector<std::string> names() { return {std::string(Ts::kName)...}; }
  static bool contains(std::string_view name) { return ((name == Ts::kName) || ...); }
  // "a, b, c" for messages.
  static std::string names_text() {
    std::string t;
    ((t += (t.empty() ? "" : ", ") + std::string(Ts::kName)), ...);
    return t;
  }
  // "a (what a is), b (...)" from each T's `static constexpr const char* kSummary`, for a key's
  // description: it lists what is registered, not a copy of the list.
  static std::string summaries_text() {
    std::string t;
    ((t += (t.empty() ? "" : ", ") + std::string(Ts::kName) + " (" + Ts::kSummary + ")"), ...);
    return t;
  }
  // f.template operator()<T>() for the T called `name`; an unknown name is an internal error
  // (names are checked when the config is read).
  template <class F>
  static decltype(auto) dispatch(std::string_view name, F&& f) {
    return dispatch_from<F, Ts...>(name, f);
  }

  template <template <class> class W, class... Extra>
  using variant_of = std::variant<W<Ts>..., W<Extra>...>;

 private:
  template <class F, class First, class... Rest>
  static decltype(auto) dispatch_from(std::string_view name, F& f) {
    if (name == First::kName) return f.template operator()<First>();
    if constexpr (sizeof...(Rest) > 0)
      return dispatch_from<F, Rest...>(name, f);
    else
      throw std::logic_error("no implementation registered as '" + std::string(name) + "'");
  }
};

}  // namespace rtusim
