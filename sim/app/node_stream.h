// The node-fetch address stream of a prepared run's frame (NodeStreamBackend), into a digest or
// a trace file: what `rtusim regress` records and `rtusim trace` writes. The frame's pixels go
// in the run's order (a chip's tiles: chip_pixel_order()).
#pragma once
#include "app/pipeline.h"
#include "trace/trace_format.h"

namespace rtusim {

// Traces the prepared run's frame over `image` and returns the node stream's count and
// checksum (what `rtusim regress` records as trace.node_stream.*).
TraceDigest node_stream_digest(const Prepared& p, const MemoryImage& image);
// Traces the frame over `image` into `writer` (not finished).
void write_node_stream(const Prepared& p, const MemoryImage& image, TraceWriter& writer);
// Traces the frame over `image` through the chip's functional tier (l2.enable on) and writes
// the address of each request the L2 takes (a line an L1 missed, or a burst past the units'
// caches), in the L2's order, into `writer` (not finished).
void write_l2_stream(const Prepared& p, const MemoryImage& image, TraceWriter& writer);

}  // namespace rtusim
