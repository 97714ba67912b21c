#include "mem/node_l1.h"

#include <stdexcept>

#include "mem/l1_cache.h"
#include "util/error.h"
#include "util/stat_decl.h"
#include "util/stats.h"

namespace rtusim {
namespace {
// Stats keys of a timed cache level (the cycle tier's L1s), beside <level>.accesses/hits/misses.
const StatDecl kPrimaryMisses("<level>.primary_misses", StatKind::kCounter, "lines",
                              "misses that sent a read to the next level");
const StatDecl kMergedMisses("<level>.merged_misses", StatKind::kCounter, "lines",
                             "misses merged into a read of their line already outstanding (an "
                             "MSHR)");
const StatDecl kMshrStallCycles("<level>.mshr_stall_cycles", StatKind::kCounter, "cycles",
                                "cycles a miss waited for a free MSHR");
const StatDecl kMeanMissLatency("<level>.mean_miss_latency_cycles", StatKind::kRatio, "cycles",
                                "mean cycles from a primary miss to its line");
}  // namespace


void NodeL1::write_stats(Stats& stats, const std::string& prefix) const {
  stats.set(prefix + ".accesses", accesses());
  stats.set(prefix + ".hits", hits());
  stats.set(prefix + ".misses", misses());
  stats.set(prefix + ".primary_misses", primary_misses());
  stats.set(prefix + ".merged_misses", merged_misses());
  stats.set(prefix + ".mshr_stall_cycles", mshr_stall_cycles());
  stats.set(prefix + ".mean_miss_latency_cycles", mean_miss_latency_cycles());
}

namespace {
RtlNodeL1Maker& rtl_maker() {
  static RtlNodeL1Maker make = nullptr;
  return make;
}
}  // namespace

void register_rtl_node_l1(RtlNodeL1Maker make) { rtl_maker() = make; }

bool rtl_node_l1_linked() { return rtl_maker() != nullptr; }

std::unique_ptr<NodeL1> make_node_l1(const std::string& model, const char* name,
                                     const L1Params& p, const std::string& vcd_path) {
  if (model == "cpp") return std::make_unique<L1Cache>(name, p);
  if (model == "rtl") {
    if (!rtl_maker())
      throw InputError("l1.model = rtl: this binary was built without the RTL L1 "
                       "(-DRTUSIM_BUILD_RTL=OFF, or it does not link rtusim_rtl_l1)");
    return rtl_maker()(name, p, vcd_path);
  }
  throw std::logic_error("make_node_l1: unknown model " + model);
}

}  // namespace rtusim
