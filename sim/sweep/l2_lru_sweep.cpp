// The L2's LRU configurations in one pass: a stack per set count, a distance histogram each.
#include "sweep/l2_lru_sweep.h"

#include <algorithm>
#include <bit>
#include <map>
#include <stdexcept>

namespace rtusim {

struct L2LruSweep::Group {
  uint32_t sets = 0;
  // Several sets: distances 0..depth (depth: deeper than every configuration's ways); one set:
  // the region of the fully associative stack, 0..regions (regions: beyond every capacity).
  std::unique_ptr<SetLruStacks> stacks;
  std::unique_ptr<FullyAssocLruStack> full;
  uint32_t levels = 0;         // distances or regions, the last a miss in all
  std::vector<uint64_t> hist;  // [unit * 3 + stream][level]
};

L2LruSweep::L2LruSweep(const std::vector<CacheParams>& configs, uint32_t units,
                       uint64_t image_bytes)
    : units_(units), accesses_(size_t{units} * 3, 0) {
  if (configs.empty()) throw std::logic_error("L2LruSweep: no configuration");
  const uint32_t line_bytes = configs.front().line_bytes;
  line_shift_ = static_cast<uint32_t>(std::countr_zero(line_bytes));
  const uint64_t lines = image_bytes / line_bytes + 2;
  // Per set count: the ways (several sets) or capacities in lines (one set) it must tell apart.
  std::map<uint64_t, std::vector<uint64_t>> levels_of;
  for (const CacheParams& c : configs) {
    if (c.line_bytes != line_bytes || c.policy != "lru")
      throw std::logic_error("L2LruSweep: LRU configurations of one line size only");
    levels_of[c.sets()].push_back(c.sets() == 1 ? c.lines() : c.assoc);
  }
  std::map<uint64_t, size_t> group_of;
  for (auto& [sets, levels] : levels_of) {
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    auto g = std::make_unique<Group>();
    g->sets = static_cast<uint32_t>(sets);
    if (sets == 1) {
      g->full = std::make_unique<FullyAssocLruStack>(levels, lines);
      g->levels = static_cast<uint32_t>(levels.size()) + 1;
    } else {
      g->stacks = std::make_unique<SetLruStacks>(g->sets, static_cast<uint32_t>(levels.back()));
      g->levels = static_cast<uint32_t>(levels.back()) + 1;
    }
    g->hist.assign(size_t{units} * 3 * g->levels, 0);
    group_of[sets] = groups_.size();
    groups_.push_back(std::move(g));
  }
  for (const CacheParams& c : configs) {
    const std::vector<uint64_t>& levels = levels_of[c.sets()];
    const uint64_t level = c.sets() == 1 ? c.lines() : c.assoc;
    // One set: the capacity's index among the group's; else the ways.
    const uint32_t at = c.sets() == 1
                            ? static_cast<uint32_t>(
                                  std::lower_bound(levels.begin(), levels.end(), level) -
                                  levels.begin())
                            : static_cast<uint32_t>(level);
    where_.emplace_back(group_of[c.sets()], at);
  }
}

L2LruSweep::~L2LruSweep() = default;

void L2LruSweep::access(uint32_t unit, Stream s, uint64_t addr, uint32_t bytes) {
  const size_t k = slot(unit, s);
  const uint64_t first = addr >> line_shift_, last = (addr + bytes - 1) >> line_shift_;
  accesses_[k] += last - first + 1;
  for (const auto& g : groups_) {
    uint64_t* hist = &g->hist[k * g->levels];
    for (uint64_t line = first; line <= last; ++line)
      ++hist[g->full ? g->full->access(static_cast<uint32_t>(line)) : g->stacks->access(line)];
  }
}

L2LruSweep::Counts L2LruSweep::counts(size_t config, uint32_t unit, Stream s) const {
  const auto [group, at] = where_.at(config);
  const Group& g = *groups_[group];
  const uint64_t* hist = &g.hist[slot(unit, s) * g.levels];
  // Several sets: distance d hits with more than d ways, so the misses are d >= ways. One set:
  // region r hits in the capacities of index >= r, so the misses are r > the capacity's index.
  const uint32_t first_miss = g.full ? at + 1 : at;
  Counts c;
  c.accesses = accesses_[slot(unit, s)];
  for (uint32_t level = first_miss; level < g.levels; ++level) c.misses += hist[level];
  return c;
}

}  // namespace rtusim
