// FetchLog reuse between chunks.
#include "tracer/fetch_log.h"

namespace rtusim {

void FetchLog::clear() {
  used_ = 0;  // keeps the buffer: a chunk's log is reused by a later chunk
  rays_.clear();
  last_addr_ = {};
  last_bytes_ = {};
}

}  // namespace rtusim
