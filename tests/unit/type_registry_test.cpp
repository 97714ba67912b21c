// TypeRegistry, the by-name registry of every seam: names in list order, static dispatch to the
// named type, a variant over the types; and the real registries hold what the keys list.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "cache/policy/policies.h"
#include "cache/set_assoc_cache.h"
#include "layout/layouts.h"
#include "mem/dram/dram_backends.h"
#include "tier/tiers.h"
#include "util/type_registry.h"

namespace rtusim {
namespace {

struct Alpha {
  static constexpr const char* kName = "alpha";
  static int id() { return 1; }
};
struct Beta {
  static constexpr const char* kName = "beta";
  static int id() { return 2; }
};
template <class T>
struct Box {
  T value;
};
using Pair = TypeRegistry<Alpha, Beta>;

TEST(TypeRegistryTest, NamesAndDispatch) {
  EXPECT_EQ(Pair::names(), (std::vector<std::string>{"alpha", "beta"}));
  EXPECT_EQ(Pair::names_text(), "alpha, beta");
  EXPECT_TRUE(Pair::contains("beta"));
  EXPECT_FALSE(Pair::contains("gamma"));
  EXPECT_EQ(Pair::dispatch("alpha", []<class T>() { return T::id(); }), 1);
  EXPECT_EQ(Pair::dispatch("beta", []<class T>() { return T::id(); }), 2);
  EXPECT_THROW(Pair::dispatch("gamma", []<class T>() { return T::id(); }), std::logic_error);
  using V = Pair::variant_of<Box, int>;
  EXPECT_EQ(std::variant_size_v<V>, 3u);
  EXPECT_TRUE((std::is_same_v<std::variant_alternative_t<1, V>, Box<Beta>>));
}

TEST(TypeRegistryTest, SeamRegistries) {
  EXPECT_EQ(Layouts::names(), (std::vector<std::string>{"dfl", "odfl", "subtree"}));
  EXPECT_EQ(ReplacementPolicies::names(),
            (std::vector<std::string>{"lru", "tree-plru", "fifo", "random"}));
  EXPECT_EQ(DramBackends::names(), (std::vector<std::string>{"fr-fcfs", "fixed"}));
  EXPECT_EQ(Tiers::names(), (std::vector<std::string>{"functional", "cycle", "rtl"}));
  // The cache variant holds one concrete cache per registered policy, then the virtual one.
  EXPECT_EQ(std::variant_size_v<SetAssocCache::Variant>, ReplacementPolicies::names().size() + 1);
  // Every registered policy builds a cache of that policy.
  for (const std::string& name : ReplacementPolicies::names()) {
    CacheParams p;
    p.policy = name;
    EXPECT_EQ(std::string(SetAssocCache(p).policy_name()), name);
  }
  // Every registered layout is made by its name.
  for (const std::string& name : Layouts::names())
    EXPECT_EQ(std::string(make_layout(name)->name()), name);
}

}  // namespace
}  // namespace rtusim
