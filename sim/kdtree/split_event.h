// Split-plane events of the SAH builder, packed into one 64-bit sort key (private to sim/kdtree).
#pragma once
#include <bit>
#include <cstdint>

namespace rtusim::kd_detail {

// At one plane position the sweep needs ends first, then planars, then starts (Wald & Havran).
enum class EventType : uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

// Bits 63..62 axis, 61..30 order-preserving position key, 29..28 type, 27..0 triangle id.
// Sorting the integers sorts by (axis, position, type, triangle): a total order, so every sort
// and merge of events is deterministic.
using SplitEvent = uint64_t;
constexpr uint32_t kMaxTriangles = 1u << 28;
constexpr uint32_t kTriangleMask = kMaxTriangles - 1;

// Float -> unsigned key with the same order; -0 is folded into +0 first so equal planes match.
inline uint32_t position_key(float pos) {
  const uint32_t bits = std::bit_cast<uint32_t>(pos + 0.0f);
  return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}
inline float key_position(uint32_t key) {
  return std::bit_cast<float>((key & 0x80000000u) ? (key & 0x7fffffffu) : ~key);
}

inline SplitEvent make_event(int axis, float pos, EventType type, uint32_t tri) {
  return (uint64_t(axis) << 62) | (uint64_t(position_key(pos)) << 30) |
         (uint64_t(type) << 28) | uint64_t(tri);
}
// First possible event of `axis`: the lower bound of that axis' run in a sorted list.
inline SplitEvent axis_begin_key(int axis) { return uint64_t(axis) << 62; }

inline uint32_t event_position_key(SplitEvent e) { return uint32_t(e >> 30); }
inline float event_position(SplitEvent e) { return key_position(event_position_key(e)); }
inline EventType event_type(SplitEvent e) { return EventType((e >> 28) & 3u); }
inline uint32_t event_triangle(SplitEvent e) { return uint32_t(e) & kTriangleMask; }

}  // namespace rtusim::kd_detail
