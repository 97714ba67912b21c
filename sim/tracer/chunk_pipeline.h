// Chunks of work traced on the worker threads and consumed on one thread in chunk order, with a
// bounded number of chunks alive (oneTBB's parallel_pipeline): the parallel tracers' frame.
#pragma once
#include <cstddef>
#include <vector>

#include <oneapi/tbb/parallel_pipeline.h>

#include "tracer/parallel_render.h"

namespace rtusim {

// A wavefront batch's rays per chunk: enough work per task to hide the pipeline's overhead.
inline constexpr size_t kRaysPerChunk = 256;

// Runs chunks [0, count) through trace(chunk, slot) on the worker threads and then
// consume(chunk, slot) on one thread in chunk order. A slot is reused by chunk + slots, where
// slots is chunks_per_thread per thread (it bounds the memory the slots hold).
template <class Slot, class Trace, class Consume>
void run_chunks(size_t count, Trace&& trace, Consume&& consume, int chunks_per_thread = 4) {
  const size_t slots = size_t(chunks_per_thread) * parallel_threads();
  std::vector<Slot> slot(slots);
  size_t next = 0;
  tbb::parallel_pipeline(
      slots,
      tbb::make_filter<void, size_t>(tbb::filter_mode::serial_in_order,
                                     [&](tbb::flow_control& fc) -> size_t {
                                       if (next == count) fc.stop();
                                       return next < count ? next++ : 0;
                                     }) &
          tbb::make_filter<size_t, size_t>(tbb::filter_mode::parallel,
                                            [&](size_t c) {
                                              trace(c, slot[c % slots]);
                                              return c;
                                            }) &
          tbb::make_filter<size_t, void>(tbb::filter_mode::serial_in_order,
                                         [&](size_t c) { consume(c, slot[c % slots]); }));
}

}  // namespace rtusim
