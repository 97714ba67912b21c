#include "sweep/cache_sweep.h"

#include <algorithm>
#include <bit>
#include <map>
#include <set>
#include <stdexcept>

#include "sweep/paired_set_stacks.h"

namespace rtusim {

// LRU engines sharing one line size: the line stream is decoded once for all of them. The set
// counts are walked in increasing order by a PairedSetStacks when every one is at most 8 ways
// deep, else one SetLruStacks after the other; either way the walk stops at the first set count
// where the line is the most recent (Hill & Smith's set refinement: it is then the most recent
// at every larger set count, where the access changes nothing).
struct CacheSweep::LineGroup {
  uint32_t shift = 0;
  uint32_t coarser = 0;  // shift - the encoded lines' shift
  PerTag accesses{};
  PerTag repeats{};               // accesses to the line accessed just before
  uint64_t last_line = ~uint64_t{0};
  std::unique_ptr<FullyAssocLruStack> full;
  std::vector<uint64_t> full_capacities;         // lines, increasing
  std::vector<PerTag> full_hist;                 // per region (+1: misses in all)
  std::vector<uint64_t> sets;                    // per set-count engine, increasing
  std::unique_ptr<PairedSetStacks> paired;       // the engines, when all are shallow
  std::vector<SetLruStacks> set_stacks;          // the engines otherwise
  size_t engines = 0;                            // walked (paired: with its padding)
  uint32_t stride = 0;                           // histogram entries per engine
  std::vector<uint64_t> hist;     // [tag][engine][distance (depth: beyond)]
  std::vector<uint64_t> stopped;  // [tag][e]: walks that stopped before engine e

  // Makes the set-count engines: `depth_of` maps set count -> most ways.
  void add_sets(const std::vector<std::pair<uint64_t, uint32_t>>& depth_of) {
    std::vector<uint32_t> depths;
    for (const auto& [n, depth] : depth_of) {
      sets.push_back(n);
      depths.push_back(depth);
    }
    const uint32_t deepest = depths.empty() ? 0 : *std::max_element(depths.begin(), depths.end());
    if (deepest <= PairedSetStacks::kMaxDepth) {
      paired = std::make_unique<PairedSetStacks>(sets, depths);
      engines = paired->size();
      stride = PairedSetStacks::kStride;
    } else {
      for (size_t e = 0; e < sets.size(); ++e)
        set_stacks.emplace_back(static_cast<uint32_t>(sets[e]), depths[e]);
      engines = set_stacks.size();
      stride = deepest + 1;
    }
    hist.assign(kTags * engines * stride, 0);
    stopped.assign(kTags * (engines + 1), 0);
  }

  // Takes a chunk's encoded lines at this group's line size: a line that is the previous
  // word's line again within one fetch is no access of its own here, one that repeats the line
  // just accessed is a hit at distance 0 everywhere and changes no state.
  void feed(const SweepChunk& chunk) {
    for (int t = 0; t < kTags; ++t) {
      accesses[t] += chunk.repeats[t];
      repeats[t] += chunk.repeats[t];
    }
    constexpr size_t kAhead = 4;  // lines between a line's prefetch and its access
    const uint32_t* words = chunk.words.data();
    const size_t n = chunk.n_words;
    for (size_t i = 0; i < n; ++i) {
      if (full && i + kAhead < n) full->prefetch((words[i + kAhead] >> 3) >> coarser);
      const uint32_t word = words[i], fine = word >> 3, tag = (word >> 1) & 3;
      const uint32_t line = fine >> coarser;
      if ((word & 1) && ((fine - 1) >> coarser) == line) continue;
      ++accesses[tag];
      if (line == last_line) {
        ++repeats[tag];
        continue;
      }
      last_line = line;
      if (full) ++full_hist[full->access(line)][tag];
      if (engines == 0) continue;
      uint64_t* h = hist.data() + tag * engines * stride;
      size_t stop = engines;
      if (paired) {
        stop = paired->access(line, h);
      } else {
        for (size_t e = 0; e < set_stacks.size(); ++e) {
          const uint32_t d = set_stacks[e].access(line);
          ++h[e * stride + d];
          if (d == 0) {
            stop = e + 1;
            break;
          }
        }
      }
      ++stopped[tag * (engines + 1) + stop];
    }
  }

  // Hits of a cache that hits on every histogram entry below `n`.
  static PerTag hits_below(const std::vector<PerTag>& hist, uint32_t n) {
    PerTag h{};
    for (uint32_t d = 0; d < n; ++d)
      for (int t = 0; t < kTags; ++t) h[t] += hist[d][t];
    return h;
  }

  // Hits of engine e's caches of `ways` ways: distances below `ways` where it was walked, and
  // every walk that stopped before it.
  PerTag set_hits(size_t e, uint32_t ways) const {
    PerTag h{};
    for (int t = 0; t < kTags; ++t) {
      for (uint32_t d = 0; d < ways; ++d) h[t] += hist[(t * engines + e) * stride + d];
      for (size_t s = 0; s <= e; ++s) h[t] += stopped[t * (engines + 1) + s];
    }
    return h;
  }
};

CacheSweep::CacheSweep(const std::vector<CacheParams>& configs, uint64_t image_bytes,
                       unsigned parts) {
  // Group the LRU configurations by line size, then by set count.
  std::map<uint32_t, std::map<uint64_t, uint32_t>> depth;  // line -> sets -> most ways
  std::map<uint32_t, std::set<uint64_t>> full;             // line -> one-set capacities
  for (const CacheParams& c : configs) {
    if (c.policy != "lru") continue;
    if (c.sets() == 1) {
      full[c.line_bytes].insert(c.assoc);
    } else {
      uint32_t& d = depth[c.line_bytes][c.sets()];
      d = std::max(d, c.assoc);
    }
  }
  // Each line size's engines, split into up to `parts` groups of about equal work (the one-set
  // stack counted as two set counts). A group walks its own set counts with its own early exit,
  // so the split changes the work, never the counts.
  struct Part {
    int group;
    std::set<uint64_t> sets;
  };
  std::map<uint32_t, std::vector<Part>> parts_of_line;
  // The encoded lines are of the finest LRU line size: 29 bits of line number per word.
  if (!depth.empty() || !full.empty()) {
    finest_shift_ = static_cast<uint32_t>(
        std::countr_zero(std::min(depth.empty() ? UINT32_MAX : depth.begin()->first,
                                  full.empty() ? UINT32_MAX : full.begin()->first)));
    lines_ = (image_bytes >> finest_shift_) + 1;
    if (lines_ >= (uint64_t{1} << 29))
      throw std::logic_error("CacheSweep: line numbers must fit 29 bits");
  }
  for (const CacheParams& c : configs) {
    if (c.policy != "lru" || parts_of_line.count(c.line_bytes)) continue;
    const uint32_t shift = static_cast<uint32_t>(std::countr_zero(c.line_bytes));
    const auto full_it = full.find(c.line_bytes);
    const auto& set_depths = depth[c.line_bytes];
    const size_t weight = set_depths.size() + (full_it != full.end() ? 2 : 0);
    const size_t n = std::max<size_t>(1, std::min<size_t>(std::max(1u, parts), weight));
    auto next_sets = set_depths.begin();
    size_t done = 0;
    for (size_t part = 0; part < n; ++part) {
      auto g = std::make_unique<LineGroup>();
      g->shift = shift;
      g->coarser = shift - finest_shift_;
      if (part == 0 && full_it != full.end()) {
        g->full_capacities.assign(full_it->second.begin(), full_it->second.end());
        g->full = std::make_unique<FullyAssocLruStack>(g->full_capacities,
                                                       (image_bytes >> shift) + 1);
        g->full_hist.assign(g->full_capacities.size() + 1, PerTag{});
        done += 2;
      }
      Part p{static_cast<int>(groups_.size()), {}};
      const size_t until = weight * (part + 1) / n;
      std::vector<std::pair<uint64_t, uint32_t>> part_depths;
      for (; next_sets != set_depths.end() && (done < until || part + 1 == n); ++next_sets, ++done) {
        part_depths.push_back(*next_sets);
        p.sets.insert(next_sets->first);
      }
      g->add_sets(part_depths);
      parts_of_line[c.line_bytes].push_back(std::move(p));
      groups_.push_back(std::move(g));
    }
  }
  // Where each configuration's counts come from.
  for (const CacheParams& c : configs) {
    Where w;
    if (c.policy == "lru") {
      const std::vector<Part>& line_parts = parts_of_line.at(c.line_bytes);
      w.line_group = line_parts.front().group;
      for (const Part& p : line_parts)
        if (p.sets.count(c.sets())) w.line_group = p.group;
      const LineGroup& g = *groups_[w.line_group];
      if (c.sets() == 1) {
        const auto& caps = g.full_capacities;
        w.level = static_cast<uint32_t>(std::find(caps.begin(), caps.end(), c.assoc) - caps.begin());
      } else {
        w.engine = static_cast<int>(std::find(g.sets.begin(), g.sets.end(), c.sets()) - g.sets.begin());
        w.level = c.assoc;
      }
    } else {
      w.side_cache = static_cast<int>(side_.size());
      side_.push_back(SideCache{SetAssocCache(c)});
    }
    where_.push_back(w);
  }
  keeps_fetches_ = !side_.empty();
  encodes_ = !groups_.empty();
}

CacheSweep::~CacheSweep() = default;

unsigned CacheSweep::parts_for(const std::vector<CacheParams>& configs, unsigned threads) {
  std::set<uint32_t> lines;
  for (const CacheParams& c : configs)
    if (c.policy == "lru") lines.insert(c.line_bytes);
  const auto n = static_cast<unsigned>(std::max<size_t>(1, lines.size()));
  return (std::max(1u, threads) + n - 1) / n;
}

void CacheSweep::grow(SweepChunk& chunk, uint64_t first, uint64_t last) const {
  if (last >= lines_) throw std::logic_error("CacheSweep: a fetch beyond the image");
  if (chunk.n_words + (last - first) + 1 > chunk.words.size())
    chunk.words.resize(2 * chunk.words.size() + (last - first) + 1);
}

void CacheSweep::feed_task(size_t task, const SweepChunk& chunk) {
  if (task < groups_.size()) return groups_[task]->feed(chunk);
  SideCache& s = side_[task - groups_.size()];
  s.cache.visit([&](auto& cache) {
    for (const SweepFetch& f : chunk.fetches) {
      if (f.bytes() == 0) continue;
      const uint64_t before = cache.accesses();
      s.misses[f.tag()] += cache.access_range(f.addr(), f.bytes());
      s.accesses[f.tag()] += cache.accesses() - before;
    }
  });
}

void CacheSweep::feed(std::span<const SweepFetch> fetches) {
  SweepChunk chunk;
  for (const SweepFetch& f : fetches) record(chunk, f.addr(), f.bytes(), f.tag());
  for (size_t t = 0; t < tasks(); ++t) feed_task(t, chunk);
}

CacheSweep::PerTag CacheSweep::accesses(size_t i) const {
  const Where& w = where_[i];
  return w.side_cache >= 0 ? side_[w.side_cache].accesses : groups_[w.line_group]->accesses;
}

CacheSweep::PerTag CacheSweep::misses(size_t i) const {
  const Where& w = where_[i];
  if (w.side_cache >= 0) return side_[w.side_cache].misses;
  const LineGroup& g = *groups_[w.line_group];
  // A one-set cache of capacity index k hits in regions 0..k.
  const PerTag hits = w.engine < 0 ? LineGroup::hits_below(g.full_hist, w.level + 1)
                                   : g.set_hits(static_cast<size_t>(w.engine), w.level);
  PerTag m{};
  for (int t = 0; t < kTags; ++t) m[t] = g.accesses[t] - g.repeats[t] - hits[t];
  return m;
}

}  // namespace rtusim
