// Every LRU configuration of the chip's shared L2 with one line size, over the L2's input
// stream in one pass: Mattson's stack distances per set count (SetLruStacks; the one-set caches
// share a FullyAssocLruStack), kept as histograms per unit and stream, so each configuration's
// line accesses and misses per unit and stream are exactly what ChipCaches counts with that L2.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "cache/cache_params.h"
#include "layout/memory_image.h"
#include "sweep/fully_assoc_lru_stack.h"
#include "sweep/set_lru_stacks.h"

namespace rtusim {

class L2LruSweep {
 public:
  // `configs`: valid LRU caches of one line size; `units`: the initiators; `image_bytes`
  // bounds every address.
  L2LruSweep(const std::vector<CacheParams>& configs, uint32_t units, uint64_t image_bytes);
  ~L2LruSweep();

  // One request the L2 takes: `bytes` at `addr` on stream `s`, from unit `unit` (each line it
  // touches one access, in order).
  void access(uint32_t unit, Stream s, uint64_t addr, uint32_t bytes);

  struct Counts {
    uint64_t accesses = 0, misses = 0;
  };
  // Of configuration `config` (constructor order), unit `unit`'s accesses on stream `s`.
  Counts counts(size_t config, uint32_t unit, Stream s) const;

 private:
  struct Group;  // the configurations of one set count: one stack, one histogram
  size_t slot(uint32_t unit, Stream s) const { return size_t{unit} * 3 + static_cast<int>(s); }

  uint32_t line_shift_;
  uint32_t units_;
  std::vector<std::unique_ptr<Group>> groups_;
  std::vector<std::pair<size_t, uint32_t>> where_;  // per configuration: group, level
  std::vector<uint64_t> accesses_;                  // per unit and stream
};

}  // namespace rtusim
