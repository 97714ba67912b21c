// A decoded node: what traversal needs to know of a node, whatever layout stored it.
#pragma once
#include <cstdint>

namespace rtusim {

struct NodeView {
  bool leaf = true;
  uint8_t axis = 0;        // interior: split axis
  float split = 0.0f;      // interior: split position
  uint64_t below_addr = 0; // interior: child on the low side of the plane
  uint64_t above_addr = 0; // interior: child on the high side
  uint32_t prim_count = 0; // leaf: triangles in the leaf
  uint32_t inline_prim = 0;  // leaf with one triangle: its id, stored in the node
  uint64_t list_addr = 0;    // leaf with two or more: address of its u32 triangle-id list
};

}  // namespace rtusim
