// The RTL node L1 parameter combinations this build has Verilated (l1.model = rtl).
//
// Verilator fixes parameters at Verilation, so every (size, assoc, line, policy) is its own
// model; rtl_model/CMakeLists.txt lists them (RTUSIM_RTL_L1_BUILDS) and generates the table
// behind this registry. The registry is plain data: it needs neither Verilator nor SystemC, so
// config validation can use it anywhere; the SystemC models themselves are in rtusim_rtl_l1
// (rtl_model/rtl_l1_sc.h), linked only by what simulates the rtl tier.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "cache/cache_params.h"

namespace rtusim {

struct RtlL1Build {
  // Fixed in every build (l1_cache.sv defaults; rtl_model/rtl_l1_sc.h RtlL1Fixed).
  static constexpr uint32_t kMshrs = 8;
  static constexpr uint32_t kHitCycles = 2;  // request presented -> response (l1.hit_cycles)

  uint64_t size_bytes;
  uint32_t assoc;
  uint32_t line_bytes;
  std::string_view policy;  // "lru" or "tree-plru"
  std::string_view model;   // Verilated class name, e.g. "Vl1_8192_4_64_lru"

  // The behavioural cache of the same geometry and policy (its C++ twin).
  CacheParams cache() const {
    CacheParams p;
    p.size_bytes = size_bytes;
    p.assoc = assoc;
    p.line_bytes = line_bytes;
    p.policy = std::string(policy);
    return p;
  }
};

// Every built combination, in RTUSIM_RTL_L1_BUILDS order (empty when the RTL is not built).
std::span<const RtlL1Build> rtl_l1_builds();

// "8192/4/64/lru, 4096/2/32/tree-plru, ..." (size/assoc/line/policy), or "none".
std::string rtl_l1_builds_text();

// The build for the L1 params `p` (size, assoc, line, policy), or nullptr.
const RtlL1Build* find_rtl_l1_build(const CacheParams& p);

// The build for `p`; throws InputError("l1.model = rtl: no RTL build for l1.size=..., l1.assoc=...,
// l1.line=..., l1.policy=... (built: ...)") when there is none.
const RtlL1Build& rtl_l1_build(const CacheParams& p);

}  // namespace rtusim
