// The functional chip: private caches per unit, the shared L2 in turn order.
#include "chip/chip_caches.h"

#include <algorithm>
#include <functional>
#include <queue>
#include <utility>
#include <stdexcept>
#include <string>

namespace rtusim {

ChipCaches::ChipCaches(const FetchCacheParams& unit_caches, const ChipParams& chip,
                       uint32_t pixels)
    : pixel_dram_bytes_(pixels, 0) {
  units_.reserve(chip.units);
  for (uint32_t u = 0; u < chip.units; ++u) units_.push_back(Unit{FetchCache(unit_caches)});
  if (chip.l2) l2_cache_.emplace(*chip.l2);
  l2_.units.resize(chip.units);
  // The units' requests are logged for the L2 (the log's address is stable: reserved above).
  if (l2_cache_)
    for (Unit& unit : units_) unit.caches.log_next_level(&unit.pending);
}

void ChipCaches::charge(uint32_t pixel, uint64_t bytes) {
  if (pixel >= pixel_dram_bytes_.size()) [[unlikely]]
    throw std::logic_error("chip: a ray of pixel " + std::to_string(pixel) + " outside the frame's " +
                           std::to_string(pixel_dram_bytes_.size()));
  pixel_dram_bytes_[pixel] += bytes;
}

void ChipCaches::end_ray(uint32_t u, uint32_t pixel) {
  Unit& unit = units_[u];
  ++unit.rays;
  if (!l2_cache_) {
    const uint64_t now = unit.caches.dram_bytes_total();
    charge(pixel, now - unit.ray_dram_from);
    unit.ray_dram_from = now;
    return;
  }
  for (size_t i = unit.ray_first; i < unit.pending.size(); ++i) unit.pending[i].pixel = pixel;
  unit.ray_first = unit.pending.size();
}

void ChipCaches::drain(bool all) {
  if (!l2_cache_) return;
  // A unit's requests still to come have ordinals past its fetch count (or from its current
  // ray's first request on), so those at or below the lowest such bound are safe to send.
  uint64_t horizon = UINT64_MAX;
  if (!all)
    for (const Unit& unit : units_)
      horizon = std::min(horizon, unit.ray_first < unit.pending.size()
                                      ? unit.pending[unit.ray_first].ordinal - 1
                                      : unit.caches.fetches());
  // The units' next requests in turn order: a min-heap of (ordinal, unit).
  using Turn = std::pair<uint64_t, uint32_t>;
  std::priority_queue<Turn, std::vector<Turn>, std::greater<Turn>> turns;
  const auto queue_next = [&](uint32_t u) {
    const Unit& unit = units_[u];
    if (unit.head < unit.pending.size() && unit.pending[unit.head].ordinal <= horizon)
      turns.emplace(unit.pending[unit.head].ordinal, u);
  };
  for (uint32_t u = 0; u < units(); ++u) queue_next(u);
  l2_cache_->visit([&](auto& l2) {
    const uint64_t line_bytes = l2.params().line_bytes;
    while (!turns.empty()) {
      const uint32_t u = turns.top().second;
      turns.pop();
      Unit& unit = units_[u];
      const NextLevelRequest& r = unit.pending[unit.head++];
      if (l2_observer_) l2_observer_(r, u);
      const uint64_t accesses_before = l2.accesses();
      const uint64_t missed = l2.access_range(r.addr, r.bytes);
      const uint64_t accessed = l2.accesses() - accesses_before;
      const uint64_t dram_bytes = missed * line_bytes;
      for (L2Counters* c : {&l2_.streams[static_cast<int>(r.stream)], &l2_.units[u]}) {
        c->accesses += accessed;
        c->hits += accessed - missed;
        c->misses += missed;
        c->bytes_in += r.bytes;
        c->dram_bytes += dram_bytes;
      }
      charge(r.pixel, dram_bytes);
      queue_next(u);
    }
  });
  // Sent requests leave the logs (the current rays' stay, to be given their pixel).
  for (Unit& unit : units_) {
    if (unit.head < 4096 || unit.head * 2 < unit.pending.size()) continue;
    unit.pending.erase(unit.pending.begin(), unit.pending.begin() + unit.head);
    unit.ray_first -= unit.head;
    unit.head = 0;
  }
}

FetchCache::Counters ChipCaches::total_counters() const {
  FetchCache::Counters sum{};
  for (const Unit& unit : units_)
    for (int s = 0; s < FetchCache::kStreams; ++s) sum[s] += unit.caches.counters()[s];
  return sum;
}

}  // namespace rtusim
