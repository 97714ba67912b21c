#include "app/trace_replay.h"

#include <algorithm>
#include <array>
#include <bit>
#include <span>
#include <type_traits>
#include <vector>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "cache/lru4_cache.h"
#include "cache/set_assoc_cache.h"

namespace rtusim {

size_t drop_repeated_lines(std::span<uint64_t> addrs, unsigned line_shift, uint64_t& last_line) {
  size_t kept = 0, i = 0;
#if defined(__AVX512F__)
  // 8 at a time: each line against the one before (the last lane of the previous 8 shifted
  // in), the others compressed to the front. A store of 8 at kept <= i only overwrites
  // addresses already loaded. (The maskz forms, all lanes on: GCC 12 warns about the plain
  // ones' undefined source.)
  const __m128i shift = _mm_cvtsi32_si128(static_cast<int>(line_shift));
  __m512i lines_before = _mm512_set1_epi64(static_cast<long long>(last_line));
  for (; i + 8 <= addrs.size(); i += 8) {
    const __m512i a = _mm512_loadu_si512(addrs.data() + i);
    const __m512i lines = _mm512_maskz_srl_epi64(0xff, a, shift);
    const __mmask8 differs = _mm512_cmpneq_epu64_mask(
        lines, _mm512_maskz_alignr_epi64(0xff, lines, lines_before, 7));
    last_line = addrs[i + 7] >> line_shift;  // before the store may overwrite it
    _mm512_storeu_si512(addrs.data() + kept, _mm512_maskz_compress_epi64(differs, a));
    kept += static_cast<size_t>(std::popcount(static_cast<unsigned>(differs)));
    lines_before = lines;
  }
#elif defined(__AVX2__)
  // 4 at a time, as above; AVX2 has no compress, so the kept lanes are moved to the front by a
  // permutation looked up by the mask of kept lanes (its 32-bit halves, in order).
  alignas(32) static constexpr auto kToFront = [] {
    std::array<std::array<uint32_t, 8>, 16> t{};
    for (unsigned m = 0; m < 16; ++m) {
      unsigned k = 0;
      for (unsigned lane = 0; lane < 4; ++lane) {
        if (!((m >> lane) & 1)) continue;
        t[m][2 * k] = 2 * lane;
        t[m][2 * k + 1] = 2 * lane + 1;
        ++k;
      }
    }
    return t;
  }();
  const __m128i shift = _mm_cvtsi32_si128(static_cast<int>(line_shift));
  __m256i lines_before = _mm256_set1_epi64x(static_cast<long long>(last_line));
  for (; i + 4 <= addrs.size(); i += 4) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(addrs.data() + i));
    const __m256i lines = _mm256_srl_epi64(a, shift);
    // The lines one lane up, the previous 4's last in lane 0.
    const __m256i before =
        _mm256_alignr_epi8(lines, _mm256_permute2x128_si256(lines_before, lines, 0x21), 8);
    const __m256i same = _mm256_cmpeq_epi64(lines, before);
    const unsigned differs =
        ~static_cast<unsigned>(_mm256_movemask_pd(_mm256_castsi256_pd(same))) & 0xfu;
    last_line = addrs[i + 3] >> line_shift;  // before the store may overwrite it
    const __m256i to_front =
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kToFront[differs].data()));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(addrs.data() + kept),
                        _mm256_permutevar8x32_epi32(a, to_front));
    kept += static_cast<size_t>(std::popcount(differs));
    lines_before = lines;
  }
#endif
  for (; i < addrs.size(); ++i) {
    const uint64_t a = addrs[i];
    const uint64_t line = a >> line_shift;
    addrs[kept] = a;
    kept += line != last_line;
    last_line = line;
  }
  return kept;
}

namespace {

// Reads `reader` to its end through `c` (a BasicSetAssocCache or a Lru4Cache); counts fetches and
// the repeats counted instead of replayed into `out`.
template <class Cache>
void replay_chunks(TraceReader& reader, Cache& c, const CacheParams& params,
                   TraceReplayCounts& out, uint64_t& repeats) {
  const TraceHeader& h = reader.header();
  // A fetch reads node_bytes at its address (bin) or the line's size field (din with sizes); a
  // plain din line is one line access (as Dinero IV reads it). A fetch that crosses a line
  // boundary is two accesses, as in the functional tier; a chunk without one replays as
  // single-line accesses.
  std::vector<uint64_t> addrs;
  std::vector<uint32_t> sizes;
  addrs.reserve(kReplayChunkRecords);
  const uint64_t line_mask = params.line_bytes - 1;
  const unsigned line_shift = static_cast<unsigned>(std::countr_zero(params.line_bytes));
  uint64_t last_line = ~uint64_t{0};  // line of the previous single-line access (none yet)
  while (reader.next(addrs, sizes, kReplayChunkRecords)) {
    out.fetches += addrs.size();
    if (!sizes.empty()) {
      out.sized = true;
      for (size_t i = 0; i < addrs.size(); ++i) c.access_range(addrs[i], std::max(sizes[i], 1u));
      last_line = ~uint64_t{0};
      continue;
    }
    // Some fetch crosses a line boundary iff the largest offset in a line does (a max
    // reduction: vectorised, unlike an or of comparisons).
    uint64_t top_offset = 0;
    for (const uint64_t a : addrs) top_offset = std::max(top_offset, a & line_mask);
    if (top_offset + h.node_bytes > params.line_bytes) {
      // A node that would run past the top of the address space has no lines to read.
      const uint64_t top = ~uint64_t{0} - (h.node_bytes - 1);
      for (size_t i = 0; i < addrs.size(); ++i)
        if (addrs[i] > top)
          reader.fail("record " + std::to_string(out.fetches - addrs.size() + i) + ": a node of " +
                      std::to_string(h.node_bytes) + " bytes at 0x" + hex64(addrs[i]) +
                      " runs past the top of the 64-bit address space");
      for (const uint64_t a : addrs) c.access_range(a, h.node_bytes);
      last_line = ~uint64_t{0};
      continue;
    }
    // An access to the line accessed just before is a hit that changes no replacement state
    // (touching the most recent way again is a no-op for lru, tree-plru, fifo and random), so
    // such repeats are counted here and only the others go through the cache. Policies behind
    // the virtual seam get every access.
    if constexpr (std::is_same_v<Cache, BasicSetAssocCache<DynamicPolicy>>) {
      c.replay(addrs);
    } else {
      const size_t kept = drop_repeated_lines(addrs, line_shift, last_line);
      repeats += addrs.size() - kept;
      c.replay(std::span<const uint64_t>(addrs.data(), kept));
    }
  }
}

}  // namespace

TraceReplayCounts replay_trace(TraceReader& reader, const CacheParams& params) {
  TraceReplayCounts out;
  uint64_t repeats = 0;  // single-line accesses to the line accessed just before: hits
  const auto run = [&](auto& c) {
    replay_chunks(reader, c, params, out, repeats);
    out.accesses = c.accesses() + repeats;
    out.misses = c.misses();
    out.dram_bytes = c.bytes_from_dram();
  };
  validate(params, "cache");
  if (Lru4Cache::fits(params)) {
    // The default L1's shape: the recency-ordered form (the same counts, a cheaper update).
    Lru4Cache cache(params);
    run(cache);
  } else {
    SetAssocCache cache(params);
    cache.visit(run);
  }
  return out;
}

}  // namespace rtusim
