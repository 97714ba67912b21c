// The fidelity-tier seam (sim.tier): a tier is made by name for one layout's memory image,
// takes the tracer's ray batches through backend(), and writes its own stats (and, when it
// attributes traffic to pixels, the DRAM bytes of each pixel). Tiers are registered in tiers.h;
// app/simulation.cpp only orchestrates.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cache/fetch_cache.h"
#include "chip/chip_params.h"
#include "layout/memory_image.h"
#include "model/cycle_params.h"
#include "tier/functional_params.h"
#include "tracer/trace_backend.h"

namespace rtusim {

class ConfigReader;
class Stats;

// What a tier is made from: every tier's params (each uses its own).
struct TierConfig {
  FetchCacheParams caches;      // functional: the behavioural caches (each unit's)
  FunctionalParams functional;  // functional: rays in flight (interleaved mode)
  CycleParams cycle;        // cycle, rtl: the SystemC top (derived, validated)
  uint32_t pixels = 0;      // image width x height
  uint32_t width = 0;       // image width
  ChipParams chip;          // the units and the shared L2 (functional so far)
};

class TierRun {
 public:
  virtual ~TierRun() = default;
  // Where the tracer sends its ray batches.
  virtual TraceBackend& backend() = 0;
  // The tier's keys: l1.*, dram.bytes.*, traversal.node_fetches, ... (sim.cycles when timed).
  virtual void write_stats(Stats& stats) const = 0;
  // DRAM bytes of each pixel's ray tree; empty when the tier does not attribute them.
  virtual std::vector<uint64_t> pixel_dram_bytes() const { return {}; }
  // The frame is over: settles what waits for its end (the chip's L2 takes the last requests).
  // Before write_stats() and pixel_dram_bytes().
  virtual void end_frame() {}
  // Completes the outputs of a run that went well (VCD files).
  virtual void finish() {}
};

// The tier named `name` (one of tier_names()) over `image`, which must outlive it.
std::unique_ptr<TierRun> make_tier(const std::string& name, const MemoryImage& image,
                                   const TierConfig& config);
std::vector<std::string> tier_names();
// How runs of one tier for several layouts may proceed at once: on threads of one process
// (they share nothing writable), or each in a child process of its own (the tier keeps global
// state, like SystemC's kernel).
enum class LayoutConcurrency { kThreads, kProcesses };
LayoutConcurrency tier_layout_concurrency(const std::string& name);
// Reads sim.tier (declared in tier.cpp).
std::string read_tier_name(ConfigReader& r);

}  // namespace rtusim
