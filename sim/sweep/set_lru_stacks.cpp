#include "sweep/set_lru_stacks.h"

namespace rtusim {

SetLruStacks::SetLruStacks(uint32_t sets, uint32_t depth)
    : set_mask_(sets - 1), depth_(depth), stride_(depth <= kVector ? kVector : depth),
      stacks_(uint64_t{sets} * stride_ + kVector, kEmpty) {
  const auto address = reinterpret_cast<uintptr_t>(stacks_.data());
  offset_ = ((32 - address % 32) % 32) / sizeof(uint32_t);
}

}  // namespace rtusim
