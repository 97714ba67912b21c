#include "sweep/paired_set_stacks.h"

#include <stdexcept>

namespace rtusim {

PairedSetStacks::PairedSetStacks(const std::vector<uint64_t>& sets,
                                 const std::vector<uint32_t>& depths) {
  // Each set count's first entry and depth, with a one-set count appended to make pairs.
  std::vector<size_t> first;
  std::vector<uint64_t> counts;
  std::vector<uint32_t> depth;
  size_t entries = 0;
  for (size_t e = 0; e < sets.size() || counts.size() % 2; ++e) {
    const uint64_t n = e < sets.size() ? sets[e] : 1;
    const uint32_t d = e < depths.size() ? depths[e] : 1;
    if (d < 1 || d > kMaxDepth || n == 0 || (n & (n - 1)) || n > (uint64_t{1} << 32))
      throw std::logic_error("PairedSetStacks: bad set count or depth");
    first.push_back(entries);
    counts.push_back(n);
    depth.push_back(d);
    entries += n * kMaxDepth;
  }
  storage_.assign(entries + 16, kEmpty);
  const auto address = reinterpret_cast<uintptr_t>(storage_.data());
  uint32_t* stacks = storage_.data() + ((64 - address % 64) % 64) / sizeof(uint32_t);
  // Set counts 2k and 2k + 1 form pair k: first sets, set masks, the bits above their depths
  // and their lanes (the low byte for the first, the high byte for the second).
  for (size_t e = 0; e < counts.size(); e += 2)
    pair_.push_back(Pair{stacks + first[e], stacks + first[e + 1],
                         static_cast<uint32_t>(counts[e] - 1),
                         static_cast<uint32_t>(counts[e + 1] - 1), 1u << depth[e],
                         1u << depth[e + 1],
                         ((1u << depth[e]) - 1) | (((1u << depth[e + 1]) - 1) << 8)});
}

}  // namespace rtusim
