// Greedy treelet packing into 64-byte blocks and the block-cluster node writer.
#include "layout/block_cluster.h"

#include <algorithm>
#include <queue>
#include <stdexcept>

#include "layout/node_word_writer.h"
#include "util/error.h"

namespace rtusim {

std::vector<uint32_t> BlockCluster::pack(const KdTree& tree, const std::vector<double>& priority,
                                         uint64_t& slots) {
  constexpr uint32_t kNone = ~0u;
  struct Root {
    uint32_t first, second;  // second: the above sibling of a pair root, or kNone
  };
  const auto before = [&](uint32_t a, uint32_t b) {  // true when b goes before a
    return priority[a] != priority[b] ? priority[a] < priority[b] : a > b;
  };
  std::priority_queue<uint32_t, std::vector<uint32_t>, decltype(before)> candidates(before);
  std::vector<Root> pending{{0u, kNone}};  // next on top
  std::vector<uint32_t> slot_of(tree.nodes.size(), kNone);
  std::vector<uint8_t> hanging(tree.nodes.size(), 0);
  std::vector<uint32_t> parent(tree.nodes.size(), 0);
  for (uint32_t i = 0; i < tree.nodes.size(); ++i)
    if (!tree.nodes[i].is_leaf()) parent[tree.nodes[i].below] = parent[tree.nodes[i].above] = i;
  uint64_t next = 0;

  const auto place = [&](uint32_t i) {
    slot_of[i] = static_cast<uint32_t>(next++);
    const KdNode& n = tree.nodes[i];
    if (!n.is_leaf()) {
      candidates.push(n.below);
      candidates.push(n.above);
    }
  };
  std::vector<uint32_t> leftover;
  std::vector<Root> roots;
  while (true) {
    if (candidates.empty()) {
      if (pending.empty()) break;
      // Fill from the pending roots: a pair needs two free slots in this block.
      size_t pick = pending.size() - 1;
      if (next % kSlotsPerBlock == kSlotsPerBlock - 1) {
        const size_t stop = pending.size() > 8 ? pending.size() - 8 : 0;
        while (pick > stop && pending[pick].second != kNone) --pick;
      }
      if (next % kSlotsPerBlock == kSlotsPerBlock - 1 && pending[pick].second != kNone) {
        ++next;  // padding slot
      } else {
        const Root r = pending[pick];
        pending.erase(pending.begin() + static_cast<std::ptrdiff_t>(pick));
        place(r.first);
        if (r.second != kNone) place(r.second);
      }
    } else {
      place(candidates.top());
      candidates.pop();
    }
    if (next % kSlotsPerBlock != 0 || candidates.empty()) continue;
    // Block full: what hangs below it waits, siblings that both hang as one pair root.
    leftover.clear();
    while (!candidates.empty()) {
      leftover.push_back(candidates.top());
      hanging[candidates.top()] = 1;
      candidates.pop();
    }
    roots.clear();
    for (const uint32_t c : leftover) {
      if (!hanging[c]) continue;  // taken as the other half of a pair
      hanging[c] = 0;
      const KdNode& p = tree.nodes[parent[c]];
      const uint32_t sibling = c == p.below ? p.above : p.below;
      if (hanging[sibling]) {
        hanging[sibling] = 0;
        roots.push_back({p.below, p.above});
      } else {
        roots.push_back({c, kNone});
      }
    }
    pending.insert(pending.end(), roots.rbegin(), roots.rend());
  }
  slots = next;
  return slot_of;
}

MemoryImage BlockCluster::write(const KdTree& tree, const Scene& scene, const std::string& name,
                                const std::vector<uint32_t>& slot_of, uint64_t slots) {
  if (slots > kMaxSlots)
    throw InputError("layout " + name + ": tree has " + std::to_string(tree.nodes.size()) +
                     " nodes, more slots than the 25-bit node index holds");
  std::vector<uint64_t> offset(slot_of.begin(), slot_of.end());
  for (uint64_t& o : offset) o *= kNodeBytes;
  return write_8_byte_nodes(tree, scene, name, slots * kNodeBytes, offset, [&](uint32_t i) {
    const KdNode& n = tree.nodes[i];
    const uint32_t block = slot_of[i] / kSlotsPerBlock;
    const uint32_t below = slot_of[n.below], above = slot_of[n.above];
    const bool below_in = below / kSlotsPerBlock == block, above_in = above / kSlotsPerBlock == block;
    const uint32_t below_local = below % kSlotsPerBlock, above_local = above % kSlotsPerBlock;
    uint32_t w0;
    if (below_in && above_in) {
      w0 = (above_local << 7) | (below_local << 4) | (0u << 2);
    } else if (below_in) {
      w0 = (above << 7) | (below_local << 4) | (1u << 2);
    } else if (above_in) {
      w0 = (below << 7) | (above_local << 4) | (2u << 2);
    } else {
      if (above != below + 1)
        throw std::logic_error("layout " + name + ": hanging siblings not side by side");
      w0 = (below << 4) | (3u << 2);
    }
    return w0 | n.axis;
  });
}

}  // namespace rtusim
