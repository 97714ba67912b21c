// The registry of DRAM timing models (dram.backend): one entry per model, the first the
// default. A new model is its own file (a final DramBackend with kName, kSummary for the
// dram.backend description, and a (const DramParams&) constructor) plus its entry here.
#pragma once
#include <memory>

#include "mem/dram/fixed_latency_dram.h"
#include "mem/dram/fr_fcfs_dram.h"
#include "util/type_registry.h"

namespace rtusim {

using DramBackends = TypeRegistry<FrFcfsDram, FixedLatencyDram>;

// The timing model `p.backend` names, over `p`.
inline std::unique_ptr<DramBackend> make_dram_backend(const DramParams& p) {
  return DramBackends::dispatch(p.backend, [&]<class B>() -> std::unique_ptr<DramBackend> {
    return std::make_unique<B>(p);
  });
}

}  // namespace rtusim
