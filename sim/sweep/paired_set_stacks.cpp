#include "sweep/paired_set_stacks.h"

#include <stdexcept>

namespace rtusim {

PairedSetStacks::PairedSetStacks(const std::vector<uint64_t>& sets,
                                 const std::vector<uint32_t>& depths) {
  size_t entries = 0;
  for (size_t e = 0; e < sets.size() || engine_.size() % 2; ++e) {
    const uint64_t n = e < sets.size() ? sets[e] : 1;
    const uint32_t depth = e < depths.size() ? depths[e] : 1;
    if (depth < 1 || depth > kMaxDepth || n == 0 || (n & (n - 1)))
      throw std::logic_error("PairedSetStacks: bad set count or depth");
    engine_.push_back(Engine{entries, n - 1, depth});
    entries += n * kMaxDepth;
  }
  storage_.assign(entries + 16, kEmpty);
  const auto address = reinterpret_cast<uintptr_t>(storage_.data());
  stacks_ = storage_.data() + ((64 - address % 64) % 64) / sizeof(uint32_t);
}

}  // namespace rtusim
