// A behavioural set-associative cache: read-only, demand fetch, no timing. Counts per line
// access; a miss fills the line (from DRAM, line_bytes each). Used as is by the functional tier,
// and as the state model behind the cycle-tier L1.
//
// Two forms:
//  - BasicSetAssocCache<Policy>: the policy is a concrete type, its calls inlined; no allocation
//    and no virtual call per access. The hot loop for a fixed policy.
//  - SetAssocCache: the policy chosen at run time by name (CacheParams::policy). It holds one of
//    the concrete caches in a std::variant; access() dispatches once per access (a jump on the
//    variant index), replay() and visit() dispatch once per loop.
#pragma once
#include <bit>
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "cache/cache_params.h"
#include "cache/policy/policies.h"
#include "cache/replacement_policy.h"

namespace rtusim {

// Any policy registered with make_replacement_policy(), called through the virtual seam.
class DynamicPolicy {
 public:
  explicit DynamicPolicy(const CacheParams& p)
      : impl_(make_replacement_policy(p.policy, static_cast<uint32_t>(p.sets()), p.assoc,
                                      p.seed)) {}
  // A copy holds a copy of the same concrete policy (found by its name in the registry).
  DynamicPolicy(const DynamicPolicy& o)
      : impl_(ReplacementPolicies::dispatch(
            o.impl_->name(), [&]<class P>() -> std::unique_ptr<ReplacementPolicy> {
              return std::make_unique<P>(static_cast<const P&>(*o.impl_));
            })) {}
  DynamicPolicy(DynamicPolicy&&) = default;
  DynamicPolicy& operator=(DynamicPolicy o) {
    impl_ = std::move(o.impl_);
    return *this;
  }
  const char* name() const { return impl_->name(); }
  void touch(uint32_t set, uint32_t way) { impl_->touch(set, way); }
  void fill(uint32_t set, uint32_t way) { impl_->fill(set, way); }
  uint32_t victim(uint32_t set) { return impl_->victim(set); }
  bool retouch_neutral() const { return impl_->retouch_neutral(); }

 private:
  std::unique_ptr<ReplacementPolicy> impl_;
};

template <class Policy>
class BasicSetAssocCache {
 public:
  // Validates `p` (errors name the keys "cache.*"; validate with the real prefix first).
  explicit BasicSetAssocCache(const CacheParams& p)
      : params_(checked(p)),
        sets_(static_cast<uint32_t>(p.sets())),
        ways_(p.assoc),
        offset_bits_(static_cast<uint32_t>(std::countr_zero(p.line_bytes))),
        index_bits_(static_cast<uint32_t>(std::countr_zero(sets_))),
        set_mask_(uint64_t{sets_} - 1),
        policy_(make_policy(p)),
        tags_(uint64_t{sets_} * ways_, kInvalidTag),
        filled_(sets_, 0) {}

  // One access to the line holding byte `addr`: true on a hit. Updates the state.
  bool access(uint64_t addr) { return access_line(addr >> offset_bits_); }

  // Accesses every line that bytes [addr, addr + bytes) touch, in address order, each counted as
  // one access (a 36-byte triangle across a line boundary is two). Returns the lines missed.
  uint32_t access_range(uint64_t addr, uint32_t bytes) {
    if (bytes == 0) return 0;
    const uint64_t first = addr >> offset_bits_;
    const uint64_t last = (addr + bytes - 1) >> offset_bits_;
    uint32_t missed = 0;
    for (uint64_t line = first; line <= last; ++line) missed += access_line(line) ? 0 : 1;
    return missed;
  }

  // Replays single-line accesses; returns the misses among them.
  uint64_t replay(std::span<const uint64_t> addrs) {
    uint64_t missed = 0;  // a local: the counters in memory might alias the tag stores
    for (const uint64_t a : addrs) missed += lookup_fill(a >> offset_bits_) ? 0 : 1;
    accesses_ += addrs.size();
    misses_ += missed;
    return missed;
  }

  // Whether the line holding `addr` is present; changes nothing.
  bool contains(uint64_t addr) const {
    const uint64_t line = addr >> offset_bits_;
    const uint64_t* t = &tags_[(line & set_mask_) * ways_];
    for (uint32_t w = 0; w < ways_; ++w)
      if (t[w] == (line >> index_bits_)) return true;
    return false;
  }

  uint64_t accesses() const { return accesses_; }
  uint64_t hits() const { return accesses_ - misses_; }
  uint64_t misses() const { return misses_; }
  uint64_t bytes_from_dram() const { return misses_ * params_.line_bytes; }
  void reset_counters() { accesses_ = misses_ = 0; }

  const CacheParams& params() const { return params_; }
  uint32_t sets() const { return sets_; }
  uint32_t ways() const { return ways_; }
  const char* policy_name() const { return policy_.name(); }
  // Whether a repeated hit on a set's last-touched line changes no later decision (the policy's).
  bool retouch_neutral() const { return policy_.retouch_neutral(); }

 private:
  // Tags are line >> index_bits < 2^62, so all ones never matches a real tag.
  static constexpr uint64_t kInvalidTag = ~uint64_t{0};

  static const CacheParams& checked(const CacheParams& p) {
    validate(p, "cache");
    return p;
  }
  static Policy make_policy(const CacheParams& p) {
    if constexpr (std::is_constructible_v<Policy, const CacheParams&>)
      return Policy(p);
    else
      return Policy(static_cast<uint32_t>(p.sets()), p.assoc, p.seed);
  }

  bool access_line(uint64_t line) {
    ++accesses_;
    if (lookup_fill(line)) return true;
    ++misses_;
    return false;
  }

  // Looks `line` up; on a miss fills it. Touches no counter.
  bool lookup_fill(uint64_t line) {
    const uint32_t set = static_cast<uint32_t>(line & set_mask_);
    const uint64_t tag = line >> index_bits_;
    uint64_t* t = &tags_[uint64_t{set} * ways_];
    // Search every way without an early exit: a fixed trip count, so the only unpredictable
    // branch is hit versus miss.
    uint32_t hit_way = ways_;
    for (uint32_t w = 0; w < ways_; ++w) hit_way = t[w] == tag ? w : hit_way;
    if (hit_way != ways_) {
      policy_.touch(set, hit_way);
      return true;
    }
    // Invalid ways first, lowest first (no invalidation: a set fills in way order).
    const uint32_t way = filled_[set] < ways_ ? filled_[set]++ : policy_.victim(set);
    t[way] = tag;
    policy_.fill(set, way);
    return false;
  }

  CacheParams params_;
  uint32_t sets_, ways_;
  uint32_t offset_bits_, index_bits_;
  uint64_t set_mask_;
  Policy policy_;
  std::vector<uint64_t> tags_;    // [set * ways + way]
  std::vector<uint32_t> filled_;  // per set: valid ways (ways 0 .. filled-1)
  uint64_t accesses_ = 0, misses_ = 0;
};

// A cache whose policy is chosen at run time by CacheParams::policy.
class SetAssocCache {
 public:
  // One concrete cache per registered policy (policy/policies.h), then the virtual one.
  using Variant = ReplacementPolicies::variant_of<BasicSetAssocCache, DynamicPolicy>;

  // The concrete (inlined) cache for the policy named in `p`. Throws InputError on bad params.
  explicit SetAssocCache(const CacheParams& p);
  // The same policy, called through the virtual ReplacementPolicy seam (for comparison).
  static SetAssocCache through_virtual_policy(const CacheParams& p);

  bool access(uint64_t addr) {
    return std::visit([addr](auto& c) { return c.access(addr); }, impl_);
  }
  uint32_t access_range(uint64_t addr, uint32_t bytes) {
    return std::visit([addr, bytes](auto& c) { return c.access_range(addr, bytes); }, impl_);
  }
  uint64_t replay(std::span<const uint64_t> addrs) {
    return std::visit([addrs](auto& c) { return c.replay(addrs); }, impl_);
  }
  bool contains(uint64_t addr) const {
    return std::visit([addr](const auto& c) { return c.contains(addr); }, impl_);
  }
  // Calls f(concrete cache&): one dispatch for a whole loop.
  template <class F>
  decltype(auto) visit(F&& f) {
    return std::visit(std::forward<F>(f), impl_);
  }
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(std::forward<F>(f), impl_);
  }

  uint64_t accesses() const { return visit([](const auto& c) { return c.accesses(); }); }
  uint64_t hits() const { return visit([](const auto& c) { return c.hits(); }); }
  uint64_t misses() const { return visit([](const auto& c) { return c.misses(); }); }
  uint64_t bytes_from_dram() const { return visit([](const auto& c) { return c.bytes_from_dram(); }); }
  void reset_counters() {
    std::visit([](auto& c) { c.reset_counters(); }, impl_);
  }
  const CacheParams& params() const {
    return visit([](const auto& c) -> const CacheParams& { return c.params(); });
  }
  const char* policy_name() const { return visit([](const auto& c) { return c.policy_name(); }); }
  bool retouch_neutral() const {
    return visit([](const auto& c) { return c.retouch_neutral(); });
  }

 private:
  explicit SetAssocCache(Variant impl) : impl_(std::move(impl)) {}

  Variant impl_;
};

}  // namespace rtusim
