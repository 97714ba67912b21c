// The registry of DRAM timing models (dram.backend): one entry per model, the first the
// default. A new model is its own file (a final DramBackend with kName and a (const DramParams&)
// constructor) plus its entry here.
#pragma once
#include "mem/dram/fixed_latency_dram.h"
#include "mem/dram/fr_fcfs_dram.h"
#include "util/type_registry.h"

namespace rtusim {

using DramBackends = TypeRegistry<FrFcfsDram, FixedLatencyDram>;

}  // namespace rtusim
