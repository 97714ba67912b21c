// libFuzzer target: the bin and din trace readers (streamed in small chunks, so chunk
// boundaries fall everywhere) and the replay of what they return through a small cache.
#include <cstdint>
#include <vector>

#include "cache/set_assoc_cache.h"
#include "fuzz_util.h"
#include "trace/trace_format.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace rtusim;
  const auto path = fuzz::write_file("fuzz.trace", data, size);
  try {
    TraceReader reader(path);
    CacheParams params;
    params.size_bytes = 1024;
    params.assoc = 2;
    params.line_bytes = 64;
    SetAssocCache cache(params);
    std::vector<uint64_t> addrs;
    std::vector<uint32_t> sizes;
    const uint32_t node_bytes = reader.header().node_bytes;
    while (reader.next(addrs, sizes, 7)) {
      for (size_t i = 0; i < addrs.size(); ++i)
        cache.access_range(addrs[i], sizes.empty() ? node_bytes : sizes[i]);
    }
  } catch (const InputError&) {
  }
  return 0;
}
