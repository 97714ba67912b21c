// The cycle tier: the SystemC traversal unit, L1 with MSHRs and DRAM timing (CycleBackend).
// The rtl tier is the same with the Verilated node L1 (the config sets l1.model = rtl).
#pragma once
#include "model/cycle_backend.h"
#include "tier/tier.h"

namespace rtusim {

class CycleTier : public TierRun {
 public:
  static constexpr const char* kName = "cycle";
  static constexpr const char* kSummary = "SystemC unit, L1 MSHRs, DRAM timing";
  // SystemC's kernel is one global simulation: one layout per process.
  static constexpr LayoutConcurrency kLayoutConcurrency = LayoutConcurrency::kProcesses;
  CycleTier(const MemoryImage& image, const TierConfig& config) : backend_(image, config.cycle) {}

  TraceBackend& backend() override { return backend_; }
  void write_stats(Stats& stats) const override { backend_.write_stats(stats); }
  void finish() override { backend_.finish(); }

 private:
  CycleBackend backend_;
};

class RtlTier final : public CycleTier {
 public:
  static constexpr const char* kName = "rtl";
  static constexpr const char* kSummary = "cycle with the Verilated node L1";
  using CycleTier::CycleTier;
};

}  // namespace rtusim
