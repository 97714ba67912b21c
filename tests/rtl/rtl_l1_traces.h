// Address streams for the RTL L1 tests and speed bench.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rtusim::rtltest {

// Random clustered accesses: runs of nearby addresses around cluster bases in a 1 MB range,
// with returns to recent clusters (so both hits and capacity/conflict misses occur).
std::vector<uint64_t> clustered_trace(uint32_t seed, size_t count, uint32_t line_bytes);

// Random accesses to assoc + 2 lines in each of two sets: most misses evict a valid line.
std::vector<uint64_t> set_thrash_trace(uint32_t seed, size_t count, uint64_t size_bytes,
                                       uint32_t assoc, uint32_t line_bytes);

// Node-fetch addresses (issue order) of primary rays through the DFL layout of a SAH kd-tree:
// the built-in Cornell room at 128x128 with its "default" camera; the kitchen
// ($RTUSIM_SCENES/kitchen/kitchen.gltf, camera bart_camera_t0) at 128x128, or nullptr when the
// file is missing. Built once per process.
const std::vector<uint64_t>& cornell_node_trace();
const std::vector<uint64_t>* kitchen_node_trace();

}  // namespace rtusim::rtltest
