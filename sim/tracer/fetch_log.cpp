// FetchLog reuse between chunks.
#include "tracer/fetch_log.h"

namespace rtusim {

void FetchLog::clear() {
  used_ = 0;  // keeps the buffer: a chunk's log is reused by a later chunk
  rays_.clear();
  last_node_line_ = kNoLine;
  counted_node_hits_ = 0;
  direct_counts_ = {};
  ray_direct_bytes_ = 0;
}

}  // namespace rtusim
