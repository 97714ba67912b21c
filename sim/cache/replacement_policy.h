// The replacement-policy seam of the cache model. A policy keeps per-set recency state and picks
// the victim in a full set; the cache itself fills invalid ways first (lowest way first), so a
// policy is only asked for a victim when every way of the set is valid.
//
// Implementations live in policy/, one per file, registered in policy/policies.h and chosen by
// name through make_replacement_policy(). Each is a `final` class with inline members, so the cache can also
// be instantiated directly on the concrete type (BasicSetAssocCache<LruPolicy>) and the calls
// are then devirtualised and inlined; the virtual interface serves anything chosen at run time.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace rtusim {

class ReplacementPolicy {
 public:
  virtual ~ReplacementPolicy() = default;
  virtual const char* name() const = 0;
  // A hit on `way` of `set`.
  virtual void touch(uint32_t set, uint32_t way) = 0;
  // `way` of `set` was just filled (an invalid way, or the victim() just chosen).
  virtual void fill(uint32_t set, uint32_t way) = 0;
  // The way to evict from the full `set`. Leaves the recency state as it is (the fill that
  // follows updates it); the random policy advances its generator.
  virtual uint32_t victim(uint32_t set) = 0;
  // Whether a hit on the way of `set` touched or filled last changes no later victim() choice
  // (a replay may then count such repeated hits without making them). False unless known.
  virtual bool retouch_neutral() const { return false; }
};

// Names accepted by make_replacement_policy(), in the order listed in errors.
const std::vector<std::string>& known_replacement_policies();
bool is_known_replacement_policy(std::string_view name);
std::string known_replacement_policies_text();  // "lru, tree-plru, fifo, random"

// What rules out `ways` ways for the known policy `name` ("": nothing): a policy may declare a
// static ways_problem(ways), e.g. tree-plru's power of two.
std::string replacement_policy_ways_problem(std::string_view name, uint32_t ways);

// The policy called `name` for `sets` x `ways`; `seed` feeds the random policy. An unknown name
// throws InputError listing the known ones; tree-plru with a non-power-of-two `ways` throws too.
std::unique_ptr<ReplacementPolicy> make_replacement_policy(std::string_view name, uint32_t sets,
                                                           uint32_t ways, uint64_t seed);

}  // namespace rtusim
