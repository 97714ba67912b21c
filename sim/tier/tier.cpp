// Tier construction by name, and the sim.tier key.
#include "tier/tier.h"

#include "config/param.h"
#include "tier/tiers.h"

namespace rtusim {
namespace {
const StringParam kTier("sim.tier", FunctionalTier::kName, Tiers::names(), "",
                        "fidelity: " + Tiers::summaries_text());
}  // namespace

std::unique_ptr<TierRun> make_tier(const std::string& name, const MemoryImage& image,
                                   const TierConfig& config) {
  return Tiers::dispatch(name, [&]<class T>() -> std::unique_ptr<TierRun> {
    return std::make_unique<T>(image, config);
  });
}

std::vector<std::string> tier_names() { return Tiers::names(); }

LayoutConcurrency tier_layout_concurrency(const std::string& name) {
  return Tiers::dispatch(name, []<class T>() { return T::kLayoutConcurrency; });
}

std::string read_tier_name(ConfigReader& r) { return kTier.read(r); }

}  // namespace rtusim
