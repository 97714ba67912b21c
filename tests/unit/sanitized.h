// Whether this test binary runs under AddressSanitizer (scripts/sanitize.sh). The heaviest unit
// tests do a smaller share of their loops there: ASan+UBSan run them 10-30x slower, and the
// same code paths are taken with fewer iterations. The full loops run in every other build.
#pragma once
#include <cstddef>

namespace rtusim::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

// `n` iterations, or a quarter of them (at least one) under a sanitizer.
constexpr size_t sanitized_share(size_t n) { return kSanitized ? (n + 3) / 4 : n; }

}  // namespace rtusim::testing
