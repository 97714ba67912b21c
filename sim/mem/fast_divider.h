// Exact unsigned 64-bit division by a divisor fixed at construction, without the divide
// instruction (tens of cycles on x86): the cycle tier converts picoseconds to cycles and
// addresses to lines, rows and banks several times per simulated fetch.
//
// A power of two is a shift. Otherwise q = high 64 bits of n * floor(2^64 / d), which is
// floor(n / d) or one less (floor(2^64 / d) > 2^64 / d - 1, so n * m / 2^64 > n / d - 1), and
// one comparison of the remainder corrects it. Exact for every n.
#pragma once
#include <bit>
#include <cstdint>

namespace rtusim {

class FastDivider {
  __extension__ using Wide = unsigned __int128;  // a GCC/Clang type: -Wpedantic is told so

 public:
  explicit FastDivider(uint64_t d = 1)
      : d_(d), pow2_(std::has_single_bit(d)),
        shift_(static_cast<uint32_t>(std::countr_zero(d))),
        inverse_(pow2_ ? 0 : ~uint64_t{0} / d) {}

  uint64_t divisor() const { return d_; }

  // floor(n / d).
  uint64_t div(uint64_t n) const {
    if (pow2_) return n >> shift_;
    uint64_t q = static_cast<uint64_t>((static_cast<Wide>(n) * inverse_) >> 64);
    q += n - q * d_ >= d_;
    return q;
  }
  // n mod d.
  uint64_t mod(uint64_t n) const { return n - div(n) * d_; }
  // ceil(n / d), for n + d - 1 below 2^64.
  uint64_t div_up(uint64_t n) const { return div(n + d_ - 1); }

 private:
  uint64_t d_;
  bool pow2_;
  uint32_t shift_;
  uint64_t inverse_;  // floor(2^64 / d) when d is not a power of two
};

}  // namespace rtusim
