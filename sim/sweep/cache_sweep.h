// Many cache configurations over one fetch stream in one pass: the sweep's memory side.
// LRU configurations of one line size share a stack-distance pass (PairedSetStacks, or
// SetLruStacks per set count when one is deeper than 8 ways, FullyAssocLruStack for the one-set
// caches; the set counts of a line size may be split into
// parts walked by different threads); FIFO, tree-PLRU and random are simulated side by
// side, each in its own cache, over the same decoded stream. Every configuration counts exactly
// what FetchCache counts for that cache: a fetch touching k lines is k accesses, in order.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "cache/cache_params.h"
#include "cache/set_assoc_cache.h"
#include "sweep/fully_assoc_lru_stack.h"
#include "sweep/set_lru_stacks.h"

namespace rtusim {

// One fetch of a recorded chunk: `bytes` at `addr`, on stream `tag` (Stream as an int), packed
// into 8 bytes (addr below 2^40, bytes below 2^22, tag below 4): the chunks are read once per
// line size, so their size is memory traffic.
class SweepFetch {
 public:
  SweepFetch(uint64_t addr, uint32_t bytes, uint32_t tag)
      : bits_(addr << kAddrShift | uint64_t{bytes} << kTagBits | tag) {
    if ((addr >> (64 - kAddrShift)) != 0 || (bytes >> (kAddrShift - kTagBits)) != 0 || tag >= 4)
      throw std::logic_error("SweepFetch: address, size or tag out of range");
  }
  uint64_t addr() const { return bits_ >> kAddrShift; }
  uint32_t bytes() const {
    return static_cast<uint32_t>(bits_ >> kTagBits) & ((uint32_t{1} << (kAddrShift - kTagBits)) - 1);
  }
  uint32_t tag() const { return static_cast<uint32_t>(bits_) & ((1u << kTagBits) - 1); }

 private:
  static constexpr unsigned kTagBits = 2, kAddrShift = 24;
  uint64_t bits_;
};

// A chunk of the stream as the sweep's tasks read it, filled by CacheSweep::record(): the
// fetches themselves when side-by-side caches simulate them, and their LRU line stream, encoded
// once for every line size: one word per line a fetch touches at the sweep's finest LRU line
// size, line << 3 | tag << 1 | (1 when it is not the fetch's first line), without the first
// lines that repeat the line just before (counted in `repeats`: at every line size an access
// that hits and changes nothing).
struct SweepChunk {
  size_t recorded = 0;              // fetches
  std::vector<SweepFetch> fetches;  // empty when no side-by-side cache reads them
  std::vector<uint32_t> words;      // the first `n_words` are this chunk's (the vector only grows)
  size_t n_words = 0;
  std::array<uint64_t, 3> repeats{};  // per tag
  void clear() {
    recorded = 0;
    fetches.clear();
    n_words = 0;
    repeats = {};
  }
};

class CacheSweep {
 public:
  static constexpr int kTags = 3;
  using PerTag = std::array<uint64_t, kTags>;
  static_assert(std::is_same_v<PerTag, decltype(SweepChunk::repeats)>);

  // `configs` are valid (validate()); `image_bytes` bounds every address. The LRU set counts
  // of each line size are split into up to `parts` groups of about equal work (one per thread
  // that will feed it; one part walks fewest stacks).
  CacheSweep(const std::vector<CacheParams>& configs, uint64_t image_bytes, unsigned parts = 1);
  // The parts per line size that give `threads` workers a task each: the line sizes share out
  // the threads (a split costs a second walk of the line stream).
  static unsigned parts_for(const std::vector<CacheParams>& configs, unsigned threads);
  ~CacheSweep();

  // Feeds a chunk of fetches, in order, to every configuration, on this thread (the reference
  // SweepPipeline's threads are checked against).
  void feed(std::span<const SweepFetch> fetches);
  // The same work in two steps: record() every fetch into chunks, in order, then feed_task()
  // every task (a line-size group, or a side-by-side cache) every chunk, each task its chunks in
  // order, whichever tasks run at the same time (SweepPipeline).
  [[gnu::always_inline]] void record(SweepChunk& chunk, uint64_t addr, uint32_t bytes,
                                     uint32_t tag) {
    ++chunk.recorded;
    if (keeps_fetches_) [[unlikely]]
      chunk.fetches.push_back({addr, bytes, tag});
    if (bytes == 0 || !encodes_) return;
    const uint64_t first = addr >> finest_shift_, last = (addr + bytes - 1) >> finest_shift_;
    if (chunk.n_words + (last - first) + 1 > chunk.words.size() || last >= lines_) [[unlikely]]
      grow(chunk, first, last);
    uint32_t* w = chunk.words.data() + chunk.n_words;
    // The first line's word is written in any case and kept unless it repeats the line before.
    w[0] = static_cast<uint32_t>(first << 3 | tag << 1);
    const bool repeat = first == last_recorded_;
    chunk.repeats[tag] += repeat;
    chunk.n_words += !repeat;
    for (uint64_t line = first + 1; line <= last; ++line)
      chunk.words[chunk.n_words++] = static_cast<uint32_t>(line << 3 | tag << 1 | 1);
    last_recorded_ = last;
  }
  bool keeps_fetches() const { return keeps_fetches_; }
  bool encodes() const { return encodes_; }
  size_t tasks() const { return groups_.size() + side_.size(); }
  void feed_task(size_t task, const SweepChunk& chunk);

  // Of configuration `i` (constructor order): line accesses and misses per tag.
  PerTag accesses(size_t i) const;
  PerTag misses(size_t i) const;
  size_t size() const { return where_.size(); }

 private:
  struct LineGroup;  // LRU engines of one line size (all its set counts, or a part of them)
  struct Where {     // how configuration i is evaluated
    int line_group = -1;    // LRU: index into groups_
    int engine = -1;        // LRU: -1 = the fully associative stack, else set_stacks index
    uint32_t level = 0;     // LRU: ways (set stacks) or capacity index (fully associative)
    int side_cache = -1;    // other policies: index into side_
  };
  struct SideCache {
    SetAssocCache cache;
    PerTag accesses{}, misses{};
  };

  // Room in `chunk` for a fetch's lines first .. last (beyond the image: an error).
  void grow(SweepChunk& chunk, uint64_t first, uint64_t last) const;

  std::vector<std::unique_ptr<LineGroup>> groups_;
  bool keeps_fetches_ = false;             // side-by-side caches read the fetches
  bool encodes_ = false;                   // LRU groups read the encoded lines
  uint32_t finest_shift_ = 0;              // of the LRU line sizes: the encoded lines'
  uint64_t lines_ = 0;                     // of the image at that size
  uint64_t last_recorded_ = ~uint64_t{0};  // the last line record() encoded
  std::vector<SideCache> side_;
  std::vector<Where> where_;
};

}  // namespace rtusim
