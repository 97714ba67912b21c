// The registry of fidelity tiers (sim.tier), fastest first. A new tier is its own file (a
// TierRun with kName, kSummary for the sim.tier description, and a (const MemoryImage&, const
// TierConfig&) constructor) plus its entry.
#pragma once
#include "tier/cycle_tier.h"
#include "tier/functional_tier.h"
#include "util/type_registry.h"

namespace rtusim {

using Tiers = TypeRegistry<FunctionalTier, CycleTier, RtlTier>;

}  // namespace rtusim
